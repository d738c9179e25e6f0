"""Demo: simplify the bundled rough samples and show before and after.

    python scripts/demo.py [--out DIR] [--epsilon E] [SAMPLE ...]

For each sample (default: all in samples/) it writes DIR/<name>_simplified.svg and
DIR/<name>_before_after.png, and prints strokes in -> out and seconds.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from core import SimplifyParams, read_sketch, simplify, write_sketch  # noqa: E402


def before_after(sketch, result, path: Path, title: str) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(10, 5.2))
    panels = ((axes[0], sketch.strokes, f"rough: {len(sketch.strokes)} strokes"),
              (axes[1], result.strokes, f"simplified: {len(result.strokes)} strokes"))
    for ax, strokes, label in panels:
        for s in strokes:
            ax.plot(*s.points.T, lw=0.9)
        ax.set_title(label)
        ax.set_aspect("equal")
        ax.invert_yaxis()  # sketch files grow y downwards
        ax.axis("off")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("samples", nargs="*", help="sample names or sketch files")
    ap.add_argument("--out", type=Path, default=ROOT / "out")
    ap.add_argument("--epsilon", type=float, default=SimplifyParams().epsilon)
    args = ap.parse_args()
    paths = [Path(s) if Path(s).exists() else ROOT / "samples" / f"{s}.scap"
             for s in args.samples] or sorted((ROOT / "samples").glob("*.scap"))
    args.out.mkdir(parents=True, exist_ok=True)
    for path in paths:
        sketch = read_sketch(path)
        result = simplify(sketch, SimplifyParams(epsilon=args.epsilon))
        svg = args.out / f"{path.stem}_simplified.svg"
        png = args.out / f"{path.stem}_before_after.png"
        write_sketch(result.to_sketch(), svg)
        before_after(sketch, result, png, f"{path.name}, epsilon {args.epsilon}")
        print(f"{path.name}: {len(sketch.strokes)} strokes -> {len(result.strokes)} in "
              f"{result.timings['total']:.2f} s; wrote {svg} and {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
