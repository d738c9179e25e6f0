"""Benchmark: shots through scripts/batch_simplify.py with --jobs 1 and 2.

    python scripts/bench_batch.py [--keyframes 48] [--repeated 40] [--files 10] [--repeats 3]

1. Distinct drawings: each of ``--keyframes`` keyframes holds one of the bundled samples,
   nudged so that no two drawings are the same (target: a speed-up of at least 1.6 with 2
   jobs on a 2-core machine).
2. Repeated drawings (cycles, copied keyframes): ``--repeated`` keyframes cycling through
   8 rough drawings of 150 strokes, each copied as its own drawing (not instanced), so
   that only their content tells they are the same; identical drawings are computed once
   in every engine (target: --jobs 2 at least 1.4 times as fast as --jobs 1).
3. Many files: ``--files`` small shots of 6 distinct keyframes each, in one batch (a farm's
   folder of shots: one pool of workers serves every file).
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


def build_shot(path: Path, keyframes: int, seed: int = 0) -> None:
    clear_scene()
    ob = make_object({}, name="Shot")
    layer = ob.data.layers["Lines"]
    rng = np.random.default_rng(seed)
    names = ["house", "cup", "fish"]
    for k in range(keyframes):
        strokes = [s + rng.normal(0, 0.002, s.shape).astype(np.float32)
                   for s in sample_points(names[k % 3])]
        fill_drawing(layer.frames.new(1 + 2 * k).drawing, strokes)
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)


def build_repeated_shot(path: Path, keyframes: int, distinct: int = 8) -> None:
    from bench_simplify import synthetic

    clear_scene()
    ob = make_object({}, name="Shot")
    layer = ob.data.layers["Lines"]
    drawings = []
    for k in range(distinct):
        strokes = synthetic(150, seed=k)
        scale = 2.0 / max(float(np.ptp(np.concatenate(strokes))), 1e-9)
        drawings.append([np.stack([p[:, 0] * scale, np.zeros(len(p)), -p[:, 1] * scale],
                                  axis=1).astype(np.float32) for p in strokes])
    for k in range(keyframes):
        fill_drawing(layer.frames.new(1 + 2 * k).drawing, drawings[k % distinct])
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)


def timed(shots: list[Path], jobs: int, out: Path) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, str(ROOT / "scripts" / "batch_simplify.py"),
                    *map(str, shots), "--output", str(out), "--jobs", str(jobs)], check=True,
                   capture_output=True)
    return time.perf_counter() - t0


def best(shots: list[Path], repeats: int) -> tuple[float, float]:
    """The fastest of ``repeats`` runs with --jobs 1 and with --jobs 2, interleaved (the
    machine's pace drifts within a minute: one run each gave 1.18x to 1.67x). One shot
    is written beside itself; several into a folder."""
    times = {1: [], 2: []}
    for _ in range(repeats):
        for jobs in (1, 2):
            out = (shots[0].with_name(f"{shots[0].stem}_{jobs}.blend") if len(shots) == 1
                   else shots[0].parent / f"out_{jobs}")
            if len(shots) > 1:
                out.mkdir(exist_ok=True)
            times[jobs].append(timed(shots, jobs, out))
    return min(times[1]), min(times[2])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--keyframes", type=int, default=48)
    ap.add_argument("--repeated", type=int, default=40)
    ap.add_argument("--files", type=int, default=10)
    ap.add_argument("--repeats", type=int, default=3, help="runs of each, the fastest kept")
    args = ap.parse_args()
    shot = Path(home) / "shot.blend"
    build_shot(shot, args.keyframes)
    one, two = best([shot], args.repeats)
    print(f"{args.keyframes} distinct keyframes: --jobs 1 {one:.2f} s, --jobs 2 {two:.2f} s, "
          f"speed-up {one / two:.2f} (target >= 1.6 on 2 cores)", flush=True)
    repeated = Path(home) / "repeated.blend"
    build_repeated_shot(repeated, args.repeated)
    one, two = best([repeated], args.repeats)
    print(f"{args.repeated} keyframes of 8 drawings repeated: --jobs 1 {one:.2f} s, --jobs 2 "
          f"{two:.2f} s, speed-up {one / two:.2f} (target >= 1.4 on 2 cores)", flush=True)
    if not args.files:
        return 0
    folder = Path(home) / "files"
    folder.mkdir()
    files = [folder / f"shot{k}.blend" for k in range(args.files)]
    for k, path in enumerate(files):
        build_shot(path, 6, seed=1 + k)
    one, two = best(files, args.repeats)
    print(f"{args.files} files of 6 distinct keyframes, one batch: --jobs 1 {one:.2f} s, "
          f"--jobs 2 {two:.2f} s, speed-up {one / two:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
