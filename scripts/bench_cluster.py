"""Benchmark: the dev sketches on a local Dask cluster of 1 and 2 worker processes, against
the local process pool (``python -m core batch`` without ``--scheduler``).

    python scripts/bench_cluster.py [--data ../shared/data] [--limit N]

Prints sketches per second for each engine and the 2-worker/1-worker ratio (target: at
least 1.7 on a 2-core machine), and checks that every engine gives the same strokes. The
cluster is Dask's own (``distributed.LocalCluster``: a scheduler and worker processes);
needs ``pip install '.[cluster]'``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "scripts")]

from bench_complex import rough_files  # noqa: E402

from core import SimplifyParams, read_sketch, simplify_all  # noqa: E402


def _strokes(outputs) -> list:
    return [[s.points.tobytes() for s in o.strokes] for o in outputs]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    ap.add_argument("--limit", type=int, default=0, help="only the first N sketches")
    args = ap.parse_args()
    files = rough_files(args.data) if args.data.is_dir() else []
    if not files:
        print(f"no sketches under {args.data}: nothing to benchmark")
        return 0
    from distributed import LocalCluster

    sketches = [read_sketch(f) for f in files[:args.limit or None]]
    params = SimplifyParams()
    rates, reference = {}, None
    runs = [("local pool, 2 processes", 2, None), ("dask, 1 worker", 1, 1),
            ("dask, 2 workers", 2, 2)]
    for name, jobs, workers in runs:
        cluster = None
        if workers:
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
        try:
            t0 = time.perf_counter()
            outputs = simplify_all(sketches, params, jobs,
                                   scheduler=cluster.scheduler_address if cluster else None)
            seconds = time.perf_counter() - t0
        finally:
            if cluster is not None:
                cluster.close()
        rates[name] = len(sketches) / seconds
        same = "" if reference is None else (
            ", same strokes" if _strokes(outputs) == reference else ", DIFFERENT strokes")
        reference = reference or _strokes(outputs)
        print(f"{name:26s} {len(sketches)} sketches in {seconds:6.1f} s: "
              f"{rates[name]:.2f} sketches/s{same}", flush=True)
    two = rates["dask, 2 workers"]
    print(f"2 workers / 1 worker: {two / rates['dask, 1 worker']:.2f} (target >= 1.7 on 2 "
          f"cores); 2 workers / local pool: {two / rates['local pool, 2 processes']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
