"""Hashes of everything ``simplify`` outputs, fresh and replayed: the check that a change
meant to keep behaviour (a refactoring, a speed-up) keeps it to the bit.

    python scripts/output_hashes.py OUT.json [--root TREE] [--data DIR] [--jobs N]
                                    [--lines complex|pen]
    python scripts/output_hashes.py --compare A.json B.json

For every rough sketch of ``../shared/data`` and every file of ``samples/``: one hash of
the output strokes (points, Bezier control points, width, pressure, style, closed, source
ids) and of the merge history (kind, cost, primitives) at the default epsilon, and one of
the strokes replayed with ``result.at`` at 0.8 and 0.5 of it; ``--lines`` picks the
output stage of a ``--root`` from before the line stage became the only one (8618027).
``--root`` imports ``core`` from another checkout (a ``git worktree`` of the commit
before), so that both trees are hashed by this same script and can be run side by
side. Only the public API is used.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import multiprocessing
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPLAYS = (0.8, 0.5)

__all__ = ["compare", "hash_sketch", "main"]


def _strokes_digest(strokes) -> str:
    h = hashlib.sha256()
    for s in strokes:
        for part in (s.points, s.bezier, s.width, s.pressure):
            h.update(b"-" if part is None else np.ascontiguousarray(part, float).tobytes())
        h.update(repr((s.style, s.closed, tuple(s.sources or ()))).encode())
    return h.hexdigest()[:16]


def _history_digest(history) -> str:
    h = hashlib.sha256()
    for m in history:
        kind = getattr(m.kind, "value", m.kind)
        h.update(repr((str(kind), m.cost.hex(), m.first, m.second, m.result)).encode())
        if m.points is not None:
            h.update(np.ascontiguousarray(m.points).tobytes())
    return h.hexdigest()[:16]


def hash_sketch(args: tuple[str, str, str | None]) -> tuple[str, dict]:
    """The hashes of one sketch (run in a worker that imports ``core`` from ``root``), with
    the output stage ``lines`` (None: the default's)."""
    root, path, lines = args
    sys.path.insert(0, root)
    from core import SimplifyParams, read_sketch, simplify

    params = SimplifyParams() if lines is None else SimplifyParams(lines=lines)
    try:
        result = simplify(read_sketch(path), params)
    except Exception as exc:  # noqa: BLE001 - a refusal is an output too
        return path, {"error": f"{type(exc).__name__}: {exc}"}
    row = {"strokes": _strokes_digest(result.strokes), "history": _history_digest(result.history),
           "count": len(result.strokes)}
    if getattr(result, "groups", None) is not None:  # which line draws each input stroke
        row["groups"] = hashlib.sha256(np.ascontiguousarray(result.groups, np.int64)
                                       .tobytes()).hexdigest()[:16]
    for f in REPLAYS:
        row[f"at{f}"] = _strokes_digest(result.at(params.epsilon * f).strokes)
    return path, row


def sketch_paths(data: Path) -> list[Path]:
    """The rough sketches of the data set (as the benchmark lists them: every ``.scap``
    but the lift3d references) and the samples. Listed here, not imported from the
    benchmark, which imports ``core`` from this checkout."""
    rough = sorted(p for p in data.rglob("*.scap") if p.name != "full_fit.scap")
    return (rough if data.is_dir() else []) + sorted((HERE.parent / "samples").glob("*.*"))


def compare(a: dict, b: dict) -> list[str]:
    """Names of the sketches whose hashes differ (or are missing on one side)."""
    return sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?")
    ap.add_argument("--root", default=str(HERE.parent), help="checkout to import core from")
    ap.add_argument("--data", default=str(HERE.parent.parent / "shared" / "data"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--compare", nargs=2, metavar=("A", "B"))
    ap.add_argument("--lines", choices=("complex", "pen"), default=None,
                    help="the output stage of a --root from before the line stage became "
                    "the only one (default: the checkout's own)")
    args = ap.parse_args(argv)
    if args.compare:
        a, b = (json.loads(Path(p).read_text()) for p in args.compare)
        differ = compare(a, b)
        print(f"{len(a)} and {len(b)} sketches hashed; {len(differ)} differ")
        for name in differ:
            print(f"  {name}: {a.get(name)} != {b.get(name)}")
        return 1 if differ else 0
    paths = sketch_paths(Path(args.data))
    rel = {str(p): (str(p.relative_to(args.data)) if str(p).startswith(args.data)
                    else p.name) for p in paths}
    with ProcessPoolExecutor(args.jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        rows = dict(pool.map(hash_sketch, [(str(Path(args.root).resolve()), str(p), args.lines)
                                           for p in paths]))
    out = {rel[p]: row for p, row in rows.items()}
    Path(args.out).write_text(json.dumps(out, indent=1, sort_keys=True))
    print(f"{len(out)} sketches hashed into {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
