"""A debug picture per pass of the pen stage (:mod:`core.lines`), as StrokeStrip draws one
per stage of its paper: what each pass made, over the input ink in grey.

    python scripts/pen_passes.py SKETCH OUT.png [--epsilon E] [--skip PASS,...]
                                 [--zoom X0,Y0,X1,Y1]

One panel per pass, in the order of ``core.lines.PASSES``: after ``pieces``, each pen piece
in its own colour; after ``follow``, each piece's samples coloured by the alive curve they
follow (grey: none); after ``group``, the pieces coloured by group; after every later pass,
its lines (closed ones dashed), with their count in the title. ``--zoom`` takes a box in
the sketch's own coordinates (the unit frame is mapped back).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from core import SimplifyParams, read_sketch, simplify  # noqa: E402
from core.lines import PASSES  # noqa: E402

__all__ = ["draw", "main"]

COLOURS = plt.cm.tab10.colors


def _panel(ax, name: str, work, ink: list[np.ndarray], back) -> str:
    """Draw what pass ``name`` made over the ink; returns the panel's title."""
    for s in ink:
        ax.plot(*s.T, lw=1.5, color="0.9")
    if name in ("pieces", "follow", "group"):
        labels = (work.labels if name == "group" and work.labels is not None
                  else np.arange(len(work.pieces)))
        if name == "follow" and work.sample_curve is not None:
            pts = back(np.concatenate(work.pieces))
            c = work.sample_curve
            ax.scatter(*pts[c < 0].T, s=1, color="0.6")
            ax.scatter(*pts[c >= 0].T, s=1, c=[COLOURS[k % 10] for k in c[c >= 0]])
            title = f"follow: {len(np.unique(c[c >= 0]))} curves followed"
        else:
            for p, k in zip(work.pieces, labels):
                ax.plot(*back(p).T, lw=0.8, color=COLOURS[int(k) % 10])
            title = (f"{name}: {len(work.pieces)} pieces" if name == "pieces" else
                     f"group: {len(np.unique(labels))} groups")
    else:
        lines = work.current_lines() if name != "bezier" else []
        for k, line in enumerate(lines):
            ax.plot(*back(line.points).T, lw=1.0, color=COLOURS[k % 10],
                    ls="--" if line.closed else "-")
        if name == "bezier":
            for k, f in enumerate(work.fitted):
                ax.plot(*back(f.points).T, lw=1.0, color=COLOURS[k % 10])
            title = f"bezier: {len(work.fitted)} strokes"
        else:
            title = f"{name}: {len(lines)} lines"
    ax.set_title(title, fontsize=9)
    return title


def draw(sketch_path: Path, out: Path, params: SimplifyParams,
         zoom: tuple[float, float, float, float] | None = None) -> list[str]:
    """Simplify ``sketch_path`` with the pen stage and draw each pass into ``out``.

    Returns:
        One line per pass: its name and what it made.
    """
    sketch = read_sketch(sketch_path)
    result = simplify(sketch, params)
    seen: list[tuple[str, object]] = []
    result.pen_passes(lambda name, work: seen.append((name, work)))
    back = result.normalisation.from_unit

    ink = [s.points for s in sketch.strokes]
    cols = 3
    rows = -(-len(seen) // cols)
    box = zoom or (*np.min([s.min(axis=0) for s in ink], axis=0),
                   *np.max([s.max(axis=0) for s in ink], axis=0))
    aspect = max(0.2, min(5.0, (box[3] - box[1]) / max(box[2] - box[0], 1e-12)))
    fig, axes = plt.subplots(rows, cols, figsize=(6 * cols, 6 * aspect * rows + 0.3 * rows),
                             squeeze=False)
    summary = [_panel(ax, name, work, ink, back) for ax, (name, work) in zip(axes.ravel(), seen)]
    for ax in axes.ravel():
        ax.set_aspect("equal")
        if zoom:
            ax.set_xlim(zoom[0], zoom[2])
            ax.set_ylim(zoom[1], zoom[3])
        ax.invert_yaxis()
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=70)
    plt.close(fig)
    return summary


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sketch", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--epsilon", type=float, default=None)
    ap.add_argument("--skip", default="", help="passes to leave out, comma-separated "
                    f"(of {', '.join(name for name, _ in PASSES)})")
    ap.add_argument("--zoom", default=None, help="X0,Y0,X1,Y1 in the sketch's coordinates")
    args = ap.parse_args()
    options = {"skip": tuple(s for s in args.skip.split(",") if s)}
    if args.epsilon is not None:
        options["epsilon"] = args.epsilon
    zoom = tuple(float(v) for v in args.zoom.split(",")) if args.zoom else None
    for line in draw(args.sketch, args.out, SimplifyParams(**options), zoom):
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
