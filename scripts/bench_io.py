"""Benchmark: the add-on's Grease Pencil I/O, 10,000 strokes of 50 points read and written.

    python scripts/bench_io.py          (the bpy wheel in this environment; target < 0.1 s)
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
home = tempfile.mkdtemp(prefix="sketchsimp-bench-")
os.environ.setdefault("BLENDER_USER_RESOURCES", os.path.join(home, "user"))
os.environ.setdefault("XDG_CACHE_HOME", os.path.join(home, "cache"))
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "scripts")]

import bpy  # noqa: E402
import numpy as np  # noqa: E402
from blender_scene import GP_DATA, load_extension  # noqa: E402

load_extension()
from sketchsimp.sketchsimp_addon.drawing import NewStrokes  # noqa: E402
from sketchsimp.sketchsimp_addon.gp_io import read_drawing, write_strokes  # noqa: E402


def main() -> int:
    n_strokes, n_points = 10_000, 50
    rng = np.random.default_rng(0)
    gp = GP_DATA.new("Bench")
    drawing = gp.layers.new("L").frames.new(1).drawing
    knots = [rng.random((n_points, 3)).astype(np.float32) for _ in range(n_strokes)]
    ones = [np.ones(n_points, np.float32)] * n_strokes
    new = NewStrokes(knots, knots, knots, [o * 0.01 for o in ones], ones,
                     [np.ones((n_points, 4), np.float32)] * n_strokes,
                     np.zeros(n_strokes, np.int32), np.zeros(n_strokes, bool))
    t0 = time.perf_counter()
    write_strokes(drawing, new)
    t1 = time.perf_counter()
    data = read_drawing(drawing)
    t2 = time.perf_counter()
    assert data.num_strokes == n_strokes and len(data.positions) == n_strokes * n_points
    print(f"Blender {bpy.app.version_string}: write {t1 - t0:.3f} s, read {t2 - t1:.3f} s, "
          f"total {t2 - t0:.3f} s for {n_strokes} strokes x {n_points} points (target < 0.1 s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
