"""Benchmark: a 48-keyframe shot through scripts/batch_simplify.py with --jobs 1 and 2.

    python scripts/bench_batch.py [--keyframes 48]

Each keyframe holds one of the bundled samples, nudged so that no two drawings are the
same. Prints the seconds of both runs and the speed-up (target: at least 1.6 with 2 jobs
on a 2-core machine).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
home = tempfile.mkdtemp(prefix="sketchsimp-bench-")
os.environ.setdefault("BLENDER_USER_RESOURCES", os.path.join(home, "user"))
os.environ.setdefault("XDG_CACHE_HOME", os.path.join(home, "cache"))
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "scripts")]

import bpy  # noqa: E402
import numpy as np  # noqa: E402
from blender_scene import clear_scene, fill_drawing, make_object, sample_points  # noqa: E402


def build_shot(path: Path, keyframes: int) -> None:
    clear_scene()
    ob = make_object({}, name="Shot")
    layer = ob.data.layers["Lines"]
    rng = np.random.default_rng(0)
    names = ["house", "cup", "fish"]
    for k in range(keyframes):
        strokes = [s + rng.normal(0, 0.002, s.shape).astype(np.float32)
                   for s in sample_points(names[k % 3])]
        fill_drawing(layer.frames.new(1 + 2 * k).drawing, strokes)
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)


def timed(shot: Path, jobs: int, out: Path) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, str(ROOT / "scripts" / "batch_simplify.py"), str(shot),
                    "--output", str(out), "--jobs", str(jobs)], check=True,
                   capture_output=True)
    return time.perf_counter() - t0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--keyframes", type=int, default=48)
    args = ap.parse_args()
    shot = Path(home) / "shot.blend"
    build_shot(shot, args.keyframes)
    one = timed(shot, 1, Path(home) / "one.blend")
    two = timed(shot, 2, Path(home) / "two.blend")
    print(f"{args.keyframes} keyframes: --jobs 1 {one:.2f} s, --jobs 2 {two:.2f} s, "
          f"speed-up {one / two:.2f} (target >= 1.6 on 2 cores)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
