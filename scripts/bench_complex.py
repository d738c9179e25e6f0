"""Benchmark: base complex of every real sketch in ../shared/data (one core, best of 3).

    python scripts/bench_complex.py [--data DIR]

Prints one row per sketch (strokes, noded pieces, nodes, curves, patches, milliseconds)
and the median and largest times. Targets: median under 30 ms, largest under 1 s.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from core import build_base_complex, clean_sketch, normalised_strokes, read_sketch  # noqa: E402


def sketch_name(path: Path, data: Path) -> str:
    rel = path.relative_to(data)
    if path.name == "full_cluster.scap":  # lift3d: .../full_clusters/designer/object/view1/...
        return f"{rel.parts[0]}/{rel.parts[3]}/{rel.parts[4]}"
    return f"{rel.parts[0]}/{path.stem}"


def rough_files(data: Path) -> list[Path]:
    return sorted(p for p in data.rglob("*.scap") if p.name != "full_fit.scap")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    files = rough_files(args.data) if args.data.is_dir() else []
    if not files:
        print(f"no sketches found under {args.data}: nothing to benchmark")
        return 0
    rows = []
    print(f"{'sketch':58s} {'strokes':>7s} {'nodes':>6s} {'curves':>6s} {'patches':>7s} "
          f"{'ms':>7s}")
    for path in files:
        strokes, _ = normalised_strokes(clean_sketch(read_sketch(path))[0])
        best = np.inf
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            cx = build_base_complex(strokes)
            best = min(best, time.perf_counter() - t0)
        rows.append(best)
        print(f"{sketch_name(path, args.data)[:58]:58s} {len(strokes):7d} {cx.num_nodes:6d} "
              f"{cx.num_curves:6d} {cx.num_patches:7d} {best * 1e3:7.1f}")
    times = np.array(rows)
    print(f"\n{len(times)} sketches: median {np.median(times) * 1e3:.1f} ms "
          f"(target < 30), largest {times.max() * 1e3:.0f} ms (target < 1000)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
