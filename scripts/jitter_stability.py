"""How much the output changes under noise nobody can see: every point of a sketch moved by
``--amount`` px in a random direction, ``--jitters`` times, each simplified at the defaults
(issue 51's stability check).

    python scripts/jitter_stability.py OUT.json [--root TREE] [--jobs N] [--every K]
                                       [--jitters 6] [--amount 0.3] [--data DIR]

Per sketch (every ``--every``-th rough sketch of ``../shared/data``, read in place): the
output's stroke count for the sketch as drawn and for each jitter, and the *spread*, the
largest count less the smallest over the jitters, as a share of the median count. Printed:
the spread's median and worst over the sketches (issue 51's targets: at most 5% and 10%),
and the sketches of the largest spread. The jitter's seed is the file's path and the
jitter's number, so a run is repeatable.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import zlib
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from quality import use_checkout

HERE = Path(__file__).resolve().parent
DATA = HERE.parent.parent / "shared" / "data"


def jittered(points: list[np.ndarray], amount: float, seed: int) -> list[np.ndarray]:
    """Each point of ``points`` moved by ``amount`` in a random direction.

    >>> out = jittered([np.zeros((5, 2))], 0.3, 1)
    >>> bool(np.allclose(np.hypot(*out[0].T), 0.3))
    True
    """
    rng = np.random.default_rng(seed)
    out = []
    for p in points:
        angle = rng.uniform(0.0, 2.0 * np.pi, len(p))
        out.append(p + amount * np.column_stack([np.cos(angle), np.sin(angle)]))
    return out


def spread(counts: list[int]) -> float:
    """The largest count less the smallest, as a share of the median.

    >>> spread([10, 11, 9, 10])
    0.2
    """
    return float((max(counts) - min(counts)) / max(np.median(counts), 1))


def one(args: tuple[str, str, str, int, float]) -> tuple[str, dict]:
    root, data, path, jitters, amount = args
    use_checkout(root)
    from core import Sketch, Stroke, read_sketch, simplify

    sketch = read_sketch(path)
    counts = []
    for k in range(jitters):
        seed = zlib.crc32(f"{Path(path).relative_to(data)}:{k}".encode())
        moved = jittered([s.points for s in sketch.strokes], amount, seed)
        counts.append(len(simplify(Sketch([Stroke(p) for p in moved], sketch.width,
                                          sketch.height)).strokes))
    drawn = len(simplify(sketch).strokes)
    return str(Path(path).relative_to(data)), {"drawn": drawn, "jittered": counts,
                                               "spread": spread(counts)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--root", default=str(HERE.parent), help="the tree whose core to run")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--every", type=int, default=1, help="every K-th sketch")
    ap.add_argument("--jitters", type=int, default=6)
    ap.add_argument("--amount", type=float, default=0.3, help="px each point moves")
    ap.add_argument("--data", type=Path, default=DATA)
    args = ap.parse_args(argv)
    files = sorted(p for p in args.data.rglob("*.scap") if p.name != "full_fit.scap")
    jobs = [(args.root, str(args.data), str(p), args.jitters, args.amount)
            for p in files[::args.every]]
    with ProcessPoolExecutor(args.jobs, mp_context=multiprocessing.get_context("spawn")) as ex:
        rows = dict(ex.map(one, jobs))
    args.out.write_text(json.dumps(rows, indent=1))
    spreads = np.array([r["spread"] for r in rows.values()])
    print(f"{len(rows)} sketches, {args.jitters} jitters of {args.amount} px: stroke-count "
          f"spread median {np.median(spreads):.1%}, worst {spreads.max():.1%} "
          f"(targets 5%, 10%)")
    for name, r in sorted(rows.items(), key=lambda kv: -kv[1]["spread"])[:5]:
        print(f"  {r['spread']:6.1%}  {r['drawn']:4d} drawn, jittered {r['jittered']}  {name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
