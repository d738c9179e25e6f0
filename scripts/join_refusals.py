"""Why pass 5 leaves passes of one line apart: the pairs of lines that run along each other
after the line stage's join (:mod:`core.lines.join`) and stay two, each with the test of
pass 5 that refuses it, counted against the labels: a grouping's loss told apart from a
fit's, and the join's tests from each other.

    python scripts/join_refusals.py [OUT.json] [--kind KIND] [--every N] [--jobs 2]
                                    [--tuning NAME=VALUE,...]

``--kind``: ``lift3d`` or ``labelled`` (every labelled sketch of ``../shared/data``, by its
strokes' clusters), or ``handwriting``, ``icons``, ``kanji``, ``product`` (the synthetic
passes of ``synthetic_passes.py``, by the curve each pass was drawn from); ``--every``
takes every Nth sketch.

A pair: the shorter line lies within :data:`REACH` d_eps of the longer, running along it
within pass 5's ``tuning.along_cos``, over ``tuning.along_share`` of its points; each
line holds at least :data:`PURE` of its pieces from one label (mixed lines are the
grouping's other loss). It is *true* where the two labels are the same. Each pair whose
median gap is at most d_eps gets the first of pass 5's tests that refuses it, asked of
the two lines alone:

- ``not along``: :func:`core.lines.fit.along_pairs` does not pair them;
- ``band``: :func:`core.lines.join.one_band` keeps a band between them;
- ``joint fit``: :func:`core.lines.fit.regroup` leaves them two (the joint line moves one
  of them more than ``tuning.join_reach``, or splits them again);
- ``each test passes``: left apart by the chains or rounds of pass 5.

Pairs farther apart than d_eps are counted as ``wider than d_eps``. Printed per reason:
true and false pairs; the true ones left apart are doubled lines, the false ones the
tests' work. And the drawing order, evidence none of the tests asks for: the share of
each drawn *interleaved* (each line has a stroke drawn before one of the other's and one
after: the pen went back and forth between them), and the median *order gap* (the
fewest strokes between one of each). Figures: ``docs/decisions.md``, "why pass 5 leaves
passes of one line apart" and "drawing order as evidence".
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from multiprocessing import Pool
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent), str(HERE)]
DATA = HERE.parent.parent / "shared" / "data"

#: pairs are sought this many d_eps apart at most
REACH = 3.0
#: a line counts where at least this share of its pieces have one label
PURE = 0.8
REASONS = ("not along", "band", "joint fit", "each test passes", "wider than d_eps")

__all__ = ["REASONS", "drawn_order", "left_apart", "main", "sketch_of"]


def sketch_of(source: str):
    """The sketch (each stroke's ``source_id`` its index) and its strokes' labels."""
    from core import Sketch, Stroke, read_sketch

    if source.endswith(".scap") and not source.endswith("full_fit.scap"):
        sketch = read_sketch(source)
        return (Sketch([Stroke(s.points, source_id=k) for k, s in enumerate(sketch.strokes)],
                       sketch.width, sketch.height), [s.cluster for s in sketch.strokes])
    from synthetic_passes import synthetic_sketch

    sketch, labels, _, _ = synthetic_sketch(source)
    return sketch, labels


def drawn_order(a: np.ndarray, b: np.ndarray) -> tuple[bool, int]:
    """Of two lines drawn by strokes ``a`` and ``b`` (their indices in drawing order):
    whether they were drawn interleaved, and the fewest strokes between one of each (0:
    a stroke of both).

    >>> drawn_order(np.array([3, 5]), np.array([4])), drawn_order(np.array([1, 2]), np.array([6]))
    ((True, 1), (False, 4))
    """
    gap = int(np.abs(a[:, None] - b[None, :]).min())
    return bool(a.min() < b.max() and b.min() < a.max()), gap


def left_apart(work, piece_label: np.ndarray, piece_source: np.ndarray) -> list[dict]:
    """The pairs (see the module) among ``work``'s lines after pass 5, given each piece's
    label and input stroke (its index in the input, in drawing order): for each, ``true``,
    ``gap`` (d_eps), ``reason`` (one of :data:`REASONS`), ``interleaved`` and
    ``order_gap`` (:func:`drawn_order`)."""
    from core.arrays.geometry import Segments, project_on, tangents
    from core.lines import fit, join

    lines, d, t = work.current_lines(), work.d, work.tuning
    label, pure = [], []
    for ln in lines:
        values, counts = np.unique(piece_label[list(ln.members)], return_counts=True)
        label.append(values[np.argmax(counts)])
        pure.append(counts.max() / counts.sum() >= PURE)
    segs = Segments.of([ln.points for ln in lines])
    lengths = np.array([ln.length for ln in lines])
    rows = []
    for i, ln in enumerate(lines):
        near, seg = segs.running_along(ln.points, tangents(ln.points, ln.closed), REACH * d,
                                       t.along_cos)
        other = segs.polyline[seg]
        for j in np.unique(other[other != i]).tolist():
            longer = lengths[j] > lengths[i] or (lengths[j] == lengths[i] and j > i)
            beside = np.unique(near[other == j])
            if not (longer and pure[i] and pure[j]
                    and len(beside) >= t.along_share * len(ln.points)):
                continue
            gap = float(np.median(project_on(lines[j].points, ln.points[beside]).distance))
            pair = np.array([[i, j]], dtype=np.intp)
            if gap > d:
                reason = "wider than d_eps"
            elif not len(fit.along_pairs([ln, lines[j]], work)):
                reason = "not along"
            elif not len(join.one_band(lines, pair, work)):
                reason = "band"
            elif len(fit.regroup(lines, pair, work)) >= len(lines):
                reason = "joint fit"
            else:
                reason = "each test passes"
            interleaved, order_gap = drawn_order(np.unique(piece_source[list(ln.members)]),
                                                 np.unique(piece_source[list(lines[j].members)]))
            rows.append({"true": bool(label[i] == label[j]), "gap": gap / d, "reason": reason,
                         "interleaved": interleaved, "order_gap": order_gap})
    return rows


def one(args: tuple[str, dict]) -> tuple[str, list[dict] | dict]:
    """The pairs of one sketch (or ``{"error": ...}``)."""
    source, tuning = args
    from core import SimplifyParams, simplify

    try:
        sketch, labels = sketch_of(source)
        result = simplify(sketch, SimplifyParams(tuning=tuning) if tuning else SimplifyParams())
        after: dict = {}
        result.pen_passes(lambda name, work: after.update({name: work}) if name == "join"
                          else None)
        work = after["join"]
    except Exception as exc:  # noqa: BLE001 - a failure is a result here
        return source, {"error": f"{type(exc).__name__}: {exc}"}
    # the cleaned strokes (those of one point and more) by their index in the input
    stroke_source = np.array([s.source_id for s in result.cleaned.strokes], dtype=np.intp)
    return source, left_apart(work, np.asarray(labels)[stroke_source][work.piece_stroke],
                              stroke_source[work.piece_stroke])


def sources(kind: str, data: Path) -> list[str]:
    if kind in ("handwriting", "icons", "kanji"):
        from synthetic_passes import DRAWINGS

        return [f"{kind}/{k}" for k in range(DRAWINGS)]
    if kind == "product":
        return sorted(str(p) for p in data.rglob("full_fit.scap"))
    under = data / "lift3d_opensketch" if kind == "lift3d" else data
    return sorted(str(p) for p in under.rglob("*.scap")
                  if p.name != "full_fit.scap" and ("label" in p.name or "cluster" in p.name))


def main(argv: list[str] | None = None) -> int:
    from quality import assignments

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?")
    ap.add_argument("--kind", default="handwriting",
                    choices=("lift3d", "labelled", "handwriting", "icons", "kanji", "product"))
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--data", type=Path, default=DATA)
    ap.add_argument("--tuning", default="", help="pen tuning to change, as name=value,...")
    args = ap.parse_args(argv)
    files = sources(args.kind, args.data.resolve())[::args.every]
    if not files:
        print(f"no {args.kind} sketches under {args.data}: nothing to count")
        return 0
    tuning = assignments(args.tuning)
    with Pool(args.jobs) as pool:
        rows = dict(pool.map(one, [(f, tuning) for f in files]))
    pairs = [r for v in rows.values() if isinstance(v, list) for r in v]
    counts = Counter((r["true"], r["reason"]) for r in pairs)
    print(f"{args.kind}: {len(files)} sketches, {len(pairs)} pairs left apart "
          f"({sum(r['true'] for r in pairs)} of one label)")
    print(f"  {'':18s} {'true':>10s} {'false':>6s}   interleaved true / false   "
          "order gap true / false")
    for reason in REASONS:
        of = [[r for r in pairs if r["reason"] == reason and r["true"] is t]
              for t in (True, False)]
        shares = " / ".join(f"{np.mean([r['interleaved'] for r in rs]):.2f}" if rs else "-"
                            for rs in of)
        gaps = " / ".join(f"{np.median([r['order_gap'] for r in rs]):.0f}" if rs else "-"
                          for rs in of)
        print(f"  {reason:18s} {counts[True, reason]:10d} {counts[False, reason]:6d}   "
              f"{shares:>24s}   {gaps:>22s}")
    errors = [k for k, v in rows.items() if isinstance(v, dict)]
    if errors:
        print(f"failures: {len(errors)} {errors[:3]}")
    if args.out:
        Path(args.out).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
