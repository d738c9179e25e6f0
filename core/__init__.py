"""SketchSimp core: sketch simplification by base-complex agglomeration.

Pure Python with numpy and shapely; never imports Blender. Internal imports are relative,
so the package works both as top-level ``core`` and as the extension's ``<pkg>.core``.

The folders are the pipeline, in the order data flows through it (``docs/design.md``):

* :mod:`core.io` reads and writes sketch files and cleans strokes into the unit frame;
* :mod:`core.complex` nodes the strokes into the base complex (nodes, curves, patches);
* :mod:`core.merge` agglomerates it: the greedy merge loop and what it measures;
* :mod:`core.lines` draws the lines: one fitted to each group of input strokes that the
  simplified complex says draw one line;
* :mod:`core.curves` fits the lines' Bezier curves, carries the ink's attributes onto them,
  and finds the regions they close;
* :mod:`core.arrays` holds the array helpers all of them share.

At the top: the plain data (:mod:`core.sketch`, :mod:`core.params`), the API
(:mod:`core.simplify`), and what applications build on it (:mod:`core.parallel`,
:mod:`core.replay_cache`). The command line (:mod:`core.cli`) is one such application.
Everything an application needs is exported here; nothing outside ``core`` reaches past it.
"""

from .complex.base_complex import BaseComplex, BaseComplexError, Patch, build_base_complex
from .curves.bezier import SAMPLES_PER_SEGMENT, evaluate_bezier, sample_bezier, subdivide_bezier
from .engine import Simplified, simplified
from .io.cleaning import CleaningReport, Normalisation, clean_sketch, normalised_strokes
from .io.files import read_sketch, write_sketch
from .merge.fourier import curve_descriptors, fd_distance, fourier_descriptor, fourier_descriptors
from .parallel import default_jobs, simplify_all
from .params import EPSILON_SOFT_MAX, PAPER_ALPHA, SimplifyParams
from .replay_cache import COVERED_EPSILON, ReplayCache
from .simplify import SimplifyResult, simplify
from .sketch import Region, Sketch, SketchError, Stroke
from .stable import held_to

__all__ = [
    "COVERED_EPSILON", "EPSILON_SOFT_MAX", "PAPER_ALPHA", "SAMPLES_PER_SEGMENT", "BaseComplex",
    "BaseComplexError",
    "build_base_complex", "clean_sketch", "CleaningReport", "curve_descriptors", "default_jobs",
    "evaluate_bezier", "fd_distance", "fourier_descriptor", "fourier_descriptors", "held_to",
    "Normalisation", "normalised_strokes", "Patch", "read_sketch", "Region", "ReplayCache",
    "sample_bezier", "Simplified", "simplified", "simplify", "simplify_all", "SimplifyParams",
    "SimplifyResult", "Sketch", "SketchError", "Stroke", "subdivide_bezier", "write_sketch",
]
