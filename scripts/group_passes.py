"""Where the grouping is won and lost: pairwise precision and recall of "these two strokes
are drawn by one line" against the labels of ``../shared/data``, after each pass of the
line stage (:mod:`core.lines`), median per data set.

    python scripts/group_passes.py [OUT.json] [--jobs 2] [--data DIR]

After ``group`` the groups are pass 3's; after every later pass, each stroke belongs to
the line that stands for most of its length (:func:`core.lines.bezier.stroke_groups`),
as the scorer's ``group_precision`` and ``group_recall`` count the output's. A pass that
raises recall and lowers precision joins lines of different labels; one that raises
precision and lowers recall splits lines of one label. Run on the line stage's own
result (``SimplifyResult.pen_passes``), so the figures after the last pass are the
scorer's.
"""

from __future__ import annotations

import argparse
import json
import sys
from multiprocessing import Pool
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent), str(HERE)]
DATA = HERE.parent.parent / "shared" / "data"
KINDS = ("lift3d_opensketch", "strokeaggregator_labels", "strokestrip_inputs")


def by_pass(path: str) -> tuple[str, dict]:
    """``{pass: (precision, recall)}`` for one labelled sketch (or ``{"error": ...}``)."""
    from metrics import pair_precision_recall

    from core import read_sketch, simplify
    from core.arrays.polylines import total_lengths
    from core.lines.bezier import stroke_groups

    sketch = read_sketch(path)
    label_of = {s.source_id: s.cluster for s in sketch.strokes}
    try:
        result = simplify(sketch)
    except Exception as exc:  # noqa: BLE001 - a failure is a result here
        return path, {"error": f"{type(exc).__name__}: {exc}"}
    labels = np.array([label_of[s.source_id] for s in result.cleaned.strokes])
    out: dict[str, tuple[float, float]] = {}

    def measure(name, work) -> None:
        if work.lines is not None:
            drawn = [(k, m) for k, line in enumerate(work.lines) for m in line.members]
        elif work.labels is not None:
            drawn = [(int(g), k) for k, g in enumerate(work.labels.tolist())]
        else:
            return
        groups = stroke_groups(drawn, work.piece_stroke, total_lengths(work.pieces),
                               len(work.strokes))
        out[name] = pair_precision_recall(groups, labels)

    result.pen_passes(measure)
    return path, out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", help="write the per-sketch figures here (JSON)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--data", type=Path, default=DATA)
    args = ap.parse_args()
    files = sorted(str(f) for f in args.data.rglob("*.scap") if f.name != "full_fit.scap")
    if not files:
        print(f"no sketches under {args.data}")
        return 2
    with Pool(args.jobs) as pool:
        found = dict(pool.map(by_pass, files, chunksize=1))
    if args.out:
        Path(args.out).write_text(json.dumps(found))
    failed = [p for p, v in found.items() if "error" in v]
    for kind in KINDS:
        rows = [v for p, v in found.items() if kind in p and "error" not in v]
        if not rows:
            continue
        print(f"{kind} ({len(rows)}): precision / recall after each pass, medians")
        for name in rows[0]:
            got = np.array([r[name] for r in rows if name in r])
            print(f"  {name:10s} {np.median(got[:, 0]):.3f} / {np.median(got[:, 1]):.3f}")
    print(f"failures: {len(failed)} {failed}")
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
