"""SketchSimp core: sketch simplification by base-complex agglomeration.

Pure Python with numpy and shapely; never imports Blender. Internal imports are relative,
so the package works both as top-level ``core`` and as the extension's ``<pkg>.core``.
"""

from .base_complex import BaseComplex, BaseComplexError, Patch, build_base_complex
from .cleaning import CleaningReport, Normalisation, clean_sketch, normalised_strokes
from .fourier import curve_descriptors, fd_distance, fourier_descriptor, fourier_descriptors
from .io import read_sketch, write_sketch
from .params import SimplifyParams
from .simplify import SimplifyResult, simplify
from .sketch import Sketch, SketchError, Stroke

__all__ = [
    "BaseComplex", "BaseComplexError", "CleaningReport", "Normalisation", "Patch", "Sketch",
    "SketchError", "Stroke", "build_base_complex", "clean_sketch", "curve_descriptors",
    "fd_distance", "fourier_descriptor", "fourier_descriptors", "normalised_strokes",
    "read_sketch", "simplify", "SimplifyParams", "SimplifyResult", "write_sketch",
]
