"""Memory is bounded by the ink, whatever a file's header says (issue 50, item 4): a canvas
far smaller than the ink it holds (a .scap header, an SVG viewBox) is simplified in the
memory the ink needs, under a 2 GB address-space cap, in a process of its own."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CAP = 2 * 1024 ** 3

RUN = textwrap.dedent("""
    import resource, sys
    import numpy as np
    resource.setrlimit(resource.RLIMIT_AS, ({cap}, {cap}))
    from core import Sketch, Stroke, simplify
    t = np.linspace(0, 1, 60)[:, None]
    ink = [Stroke({scale} * np.hstack([t, 0.3 + 0.03 * k + 0 * t])) for k in range(2)]
    result = simplify(Sketch(ink, {canvas}, {canvas}))
    # the peak of this process's own memory (ru_maxrss would count the parent's, forked)
    peak = next(int(line.split()[1]) for line in open("/proc/self/status")
                if line.startswith("VmHWM"))
    print(len(result.strokes), peak // 1024)
""")


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS caps memory on Linux")
@pytest.mark.parametrize("scale, canvas", [(1000.0, 1000.0), (1000.0, 0.01), (1e8, 1000.0)],
                         ids=["canvas as the ink", "canvas 1e-5 of the ink",
                              "ink 1e8 on a 1000 canvas"])
def test_a_canvas_far_smaller_than_its_ink_is_simplified_in_the_memory_the_ink_needs(
        scale, canvas):
    """Two loose passes of a line, sparse, so that a wider width is tried and its result
    judged for the ink it keeps at a reach the canvas shrinks: before, the ink was sampled
    at that reach, and a canvas 1e-5 of the ink asked GEOS for more than 2 GB."""
    code = RUN.format(cap=CAP, scale=scale, canvas=canvas)
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    strokes, peak_mb = map(int, done.stdout.split())
    assert 1 <= strokes <= 2 and peak_mb < 400


@pytest.mark.parametrize("error", [MemoryError("Unable to allocate 14.0 GiB"),
                                   "GEOS std::bad_alloc"])
def test_running_out_of_memory_is_said_as_a_sketch_error_naming_the_sketchs_size(
        monkeypatch, error):
    import importlib

    import numpy as np
    import shapely

    from core import Sketch, SketchError, Stroke, simplify

    def exhausted(*args, **kwargs):
        raise error if isinstance(error, MemoryError) else shapely.errors.GEOSException(error)

    monkeypatch.setattr(importlib.import_module("core.simplify"), "build_complex", exhausted)
    t = np.linspace(0, 1, 10)[:, None]
    with pytest.raises(SketchError, match=r"out of memory simplifying 1 strokes \(10 points\)"):
        simplify(Sketch([Stroke(np.hstack([t, t]))]))
