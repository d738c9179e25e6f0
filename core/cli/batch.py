"""``python -m core batch IN_DIR OUT_DIR``: every sketch file of a folder, on all cores or
on a Dask cluster (``--scheduler tcp://HOST:PORT``).

Nothing lost, nothing done twice: each output is written whole (to a temporary file in
the output folder, then renamed over its name), so an output that exists is complete;
``--resume`` skips the inputs whose output exists; a sketch that fails is reported by name
and the rest go on (exit status 1 at the end).
"""

from __future__ import annotations

import json
import os
import time
from collections import Counter
from pathlib import Path

from ..io.files import read_sketch, write_sketch
from ..parallel import simplify_all
from ..params import SimplifyParams
from ..sketch import Sketch, SketchError

__all__ = ["batch", "write_whole"]

#: temporary outputs start with this; a run that was killed may leave them behind
PARTIAL = ".partial-"


def write_whole(sketch: Sketch, target: Path) -> None:
    """Write ``sketch`` to ``target`` all at once: readers see the old file or the new one,
    never part of it."""
    partial = target.with_name(f"{PARTIAL}{os.getpid()}-{target.name}")
    try:
        write_sketch(sketch, partial)
        os.replace(partial, target)
    finally:
        partial.unlink(missing_ok=True)


def batch(in_dir: Path, out_dir: Path, params: SimplifyParams, jobs: int,
          suffix: str = ".svg", summary: Path | None = None, scheduler: str | None = None,
          resume: bool = False, connect_timeout: float = 20.0) -> int:
    """Simplify every .svg/.scap in ``in_dir`` into ``out_dir`` (on the Dask cluster at
    ``scheduler`` if given; skipping inputs whose output exists if ``resume``); returns the
    exit status."""
    if not in_dir.is_dir():
        raise SketchError(f"{in_dir}: no such folder")
    files = sorted(p for p in in_dir.iterdir() if p.suffix.lower() in (".svg", ".scap"))
    if not files:
        raise SketchError(f"{in_dir}: no .svg or .scap files")
    out_dir.mkdir(parents=True, exist_ok=True)
    for stale in out_dir.glob(PARTIAL + "*"):  # left by a run that was killed
        stale.unlink(missing_ok=True)
    t0 = time.perf_counter()

    stems = Counter(p.stem for p in files)

    def target_of(path: Path) -> Path:
        # fish.svg and fish.scap side by side would both make fish.svg: keep the suffix then
        return out_dir / ((path.name if stems[path.stem] > 1 else path.stem) + suffix)

    rows: dict[str, dict] = {}
    todo: list[tuple[Path, Sketch]] = []
    for path in files:
        target = target_of(path)
        if resume and target.exists():
            rows[path.name] = {"resumed": True, "output": str(target)}
            continue
        try:
            sketch = read_sketch(path)
        except SketchError as exc:
            rows[path.name] = {"error": str(exc)}
            continue
        rows[path.name] = {"strokes_in": len(sketch.strokes)}
        todo.append((path, sketch))

    def report(done: int, total: int, k: int) -> None:
        print(f"  {done}/{total} {todo[k][0].name}", flush=True)

    outputs = simplify_all([s for _, s in todo], params, jobs, progress=report,
                           scheduler=scheduler, connect_timeout=connect_timeout) if todo else []
    for (path, sketch), out in zip(todo, outputs):
        if isinstance(out, SketchError):
            rows[path.name] = {"error": str(out)}
            continue
        target = target_of(path)
        write_whole(Sketch(out.strokes, sketch.width, sketch.height), target)
        rows[path.name].update(strokes_out=len(out.strokes), output=str(target))
    failed = {k: v["error"] for k, v in rows.items() if "error" in v}
    done = [v for v in rows.values() if "strokes_out" in v]
    resumed = sum("resumed" in v for v in rows.values())
    seconds = time.perf_counter() - t0
    where = f"on {scheduler}" if scheduler else f"with {jobs} job(s)"
    print(f"{len(done)} of {len(files)} sketches: {sum(v['strokes_in'] for v in done)} strokes "
          f"-> {sum(v['strokes_out'] for v in done)} in {seconds:.2f} s {where}"
          + (f"; {resumed} done before, skipped" if resumed else ""))
    for name, error in failed.items():
        print(f"  failed {name}: {error}")
    if summary is not None:
        summary.write_text(json.dumps({"files": rows, "seconds": seconds, "jobs": jobs,
                                       "scheduler": scheduler, "params": params.as_dict()},
                                      indent=2))
    return 1 if failed else 0
