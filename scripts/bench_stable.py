"""Benchmark: Stable Across Frames on a drawing that moves from key to key.

    python scripts/bench_stable.py [--frames N] [--data DIR] [--only NAME,...]

Each sketch is made into a shot of keyframes: held still and redrawn (each point moved
at random, 0.1% of the diagonal D), moved 0.2% and 1% of D a frame, rotated 0.5 degrees a
frame about its middle, and moved 1% a frame while redrawn. Every keyframe is simplified
on its own ("alone") and held to the one before (:func:`core.held_to`, "held"), as the
add-on's Stable Across Frames and the batch's ``--stable`` do. Per shot and way:

- **lag**: how far the output lies from where the drawing's lines are: the mean distance
  of its points to keyframe 0's lines as drawn (simplified without the redraw noise),
  moved as the drawing was; the worst keyframe, % of D;
- **jitter**: how far the output moves from one keyframe to the next once the known
  motion is taken out (the mean distance of its points to the one before, moved as the
  drawing was), the mean over keyframes, % of D;
- **counts**: the fewest and the most strokes over the keyframes.

The target (issue 33, item 7): held, lag at most 0.1% of D and counts within 1 of each
other under motion up to 1% of D a frame; jitter no worse than alone. Redrawn, the lines
of each keyframe alone already lie 0.1 to 0.2% of D off the drawing's (the noise moves
them): the worst lag is printed for moved and redrawn shots apart. Also printed: the
machine's pace and the seconds ``held_to`` takes against ``simplify``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))

from bench_simplify import diagonal, machine_pace  # noqa: E402
from metrics import nearest_distances  # noqa: E402

from core import Sketch, Stroke, held_to, read_sketch, simplify  # noqa: E402

__all__ = ["MOTIONS", "shot", "run_shot"]

#: the ways a drawing changes from key to key: (name, shift a frame as a share of D,
#: rotation a frame in degrees, redraw noise as a share of D)
MOTIONS = (
    ("still, redrawn", 0.0, 0.0, 0.001),
    ("moved 0.2%", 0.002, 0.0, 0.0),
    ("moved 1%", 0.01, 0.0, 0.0),
    ("rotated 0.5 deg", 0.0, 0.5, 0.0),
    ("moved 1%, redrawn", 0.01, 0.0, 0.001),
)

#: the sketches of ``--data`` used by default (a cartoon, a product sketch), besides the
#: project's own house sample
DEFAULT_DATA = ("Pig01c_label_101", "designer2/lamp")


def _motion(k: int, centre: np.ndarray, shift: float, turn: float, d: float):
    """The map of keyframe 0's coordinates to keyframe ``k``'s."""
    angle = np.radians(turn * k)
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    offset = np.array([shift * d * k, 0.5 * shift * d * k])

    def move(p: np.ndarray) -> np.ndarray:
        return (p - centre) @ rot.T + centre + offset
    return move


def shot(sketch: Sketch, frames: int, shift: float, turn: float, noise: float,
         seed: int = 0) -> tuple[list[Sketch], list]:
    """The keyframes of one way of moving, and each keyframe's map from keyframe 0."""
    d = diagonal(sketch)
    pts = np.concatenate([s.points for s in sketch.strokes])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    rng = np.random.default_rng(seed)
    keys, moves = [], []
    for k in range(frames):
        move = _motion(k, centre, shift, turn, d)
        keys.append(Sketch([Stroke(move(s.points) + rng.normal(0, noise * d, s.points.shape)
                                   if noise else move(s.points))
                            for s in sketch.strokes], sketch.width, sketch.height))
        moves.append(move)
    return keys, moves


def _mean_distance(a: list[Stroke], b: list[Stroke]) -> float:
    """The mean distance of ``a``'s points to ``b``'s lines (:func:`metrics.nearest_distances`)."""
    return float(nearest_distances(np.concatenate([s.points for s in a]),
                                   [s.points for s in b]).mean())


def run_shot(keys: list[Sketch], moves: list, d: float, drawn: list[Stroke]) -> dict:
    """Alone and held: lag, jitter, counts (see the module), and seconds. ``drawn``:
    keyframe 0's lines without the redraw noise."""
    alone, held = [], []
    t_simplify = t_held = 0.0
    for sketch in keys:
        t0 = time.perf_counter()
        result = simplify(sketch)
        t1 = time.perf_counter()
        width = result.params.alpha * result.normalisation.scale
        held.append(result.strokes if not held else held_to(held[-1], result.strokes, width,
                                                            sketch.strokes))
        t_simplify += t1 - t0
        t_held += time.perf_counter() - t1
        alone.append(result.strokes)
    out = {"seconds": t_simplify, "held seconds": t_held}
    for name, seq in (("alone", alone), ("held", held)):
        lag = max(_mean_distance(s, [Stroke(move(t.points)) for t in drawn])
                  for s, move in zip(seq, moves)) / d
        jitter = []
        for k in range(1, len(seq)):
            back = [Stroke(moves[k](np.linalg.solve(  # keyframe k-1's output, moved on
                _linear(moves[k - 1]), (s.points - moves[k - 1](np.zeros(2))).T).T))
                for s in seq[k - 1]]
            jitter.append(_mean_distance(seq[k], back) / d)
        counts = [len(s) for s in seq]
        out[name] = {"lag": lag, "jitter": float(np.mean(jitter)),
                     "counts": (min(counts), max(counts))}
    return out


def _linear(move) -> np.ndarray:
    """The linear part of an affine ``move`` (columns: where it takes the unit vectors)."""
    o = move(np.zeros(2))
    return np.stack([move(np.array([1.0, 0.0])) - o, move(np.array([0.0, 1.0])) - o], axis=1)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    ap.add_argument("--only", default=",".join(DEFAULT_DATA),
                    help="sketches of --data to use besides the house sample (names)")
    args = ap.parse_args()
    pace = machine_pace()
    print(f"machine pace: {pace:.2f} s for a Python loop of 3,000,000 additions")
    paths = [ROOT / "samples" / "house.scap"]
    if args.data.is_dir():
        every = sorted(p for p in args.data.rglob("*.scap") if p.name != "full_fit.scap")
        paths += [next(p for p in every if name in str(p)) for name in args.only.split(",")
                  if any(name in str(p) for p in every)]
    print(f"{'sketch':18s} {'way':18s} | {'lag %D':>13s} | {'jitter %D':>13s} | "
          f"{'counts':>15s} | {'s simplify':>10s} {'s held':>7s}")
    print(f"{'':18s} {'':18s} | {'alone':>6s} {'held':>6s} | {'alone':>6s} {'held':>6s} | "
          f"{'alone':>7s} {'held':>7s} |")
    worst = {kind: {"lag": 0.0, "spread": 0} for kind in ("moved", "redrawn")}
    for path in paths:
        sketch = read_sketch(path)
        d = diagonal(sketch)
        drawn = simplify(sketch).strokes
        name = path.stem if path.parent.name in ("samples", "for_second_round") else \
            "/".join(path.parts[-5:-3])
        for way, shift, turn, noise in MOTIONS:
            keys, moves = shot(sketch, args.frames, shift, turn, noise)
            r = run_shot(keys, moves, d, drawn)
            a, h = r["alone"], r["held"]
            print(f"{name[:18]:18s} {way:18s} | {100 * a['lag']:6.3f} {100 * h['lag']:6.3f} | "
                  f"{100 * a['jitter']:6.3f} {100 * h['jitter']:6.3f} | "
                  f"{a['counts'][0]:3d}-{a['counts'][1]:<3d} {h['counts'][0]:3d}-"
                  f"{h['counts'][1]:<3d} | {r['seconds']:10.2f} {r['held seconds']:7.3f}")
            w = worst["redrawn" if noise else "moved"]
            w["lag"] = max(w["lag"], h["lag"])
            w["spread"] = max(w["spread"], h["counts"][1] - h["counts"][0])
    for kind, w in worst.items():
        print(f"held, worst {kind}: lag {100 * w['lag']:.3f}% of D (target 0.1%), counts "
              f"spread {w['spread']} (target 1)")
    print(f"machine pace: {machine_pace():.2f} s after ({pace:.2f} s before)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
