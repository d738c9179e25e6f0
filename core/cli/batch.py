"""``python -m core batch IN_DIR OUT_DIR``: every sketch file of a folder, on all cores."""

from __future__ import annotations

import json
import time
from pathlib import Path

from ..io.files import read_sketch, write_sketch
from ..parallel import simplify_all
from ..params import SimplifyParams
from ..sketch import Sketch, SketchError

__all__ = ["batch"]


def batch(in_dir: Path, out_dir: Path, params: SimplifyParams, jobs: int,
          suffix: str = ".svg", summary: Path | None = None) -> int:
    """Simplify every .svg/.scap in ``in_dir`` into ``out_dir``; returns the exit status."""
    if not in_dir.is_dir():
        raise SketchError(f"{in_dir}: no such folder")
    files = sorted(p for p in in_dir.iterdir() if p.suffix.lower() in (".svg", ".scap"))
    if not files:
        raise SketchError(f"{in_dir}: no .svg or .scap files")
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    sketches: list[Sketch] = []
    rows: dict[str, dict] = {}
    for path in files:
        try:
            sketches.append(read_sketch(path))
            rows[path.name] = {"strokes_in": len(sketches[-1].strokes)}
        except SketchError as exc:
            rows[path.name] = {"error": str(exc)}
    readable = [p for p in files if "error" not in rows[p.name]]

    def report(done: int, total: int) -> None:
        print(f"  {done}/{total} {readable[done - 1].name}", flush=True)

    for path, sketch, out in zip(readable, sketches,
                                 simplify_all(sketches, params, jobs, progress=report)):
        if isinstance(out, SketchError):
            rows[path.name] = {"error": str(out)}
            continue
        # fish.svg and fish.scap side by side would both make fish.svg: keep the suffix then
        clash = sum(p.stem == path.stem for p in files) > 1
        target = out_dir / ((path.name if clash else path.stem) + suffix)
        write_sketch(Sketch(out.strokes, sketch.width, sketch.height), target)
        rows[path.name].update(strokes_out=len(out.strokes), output=str(target))
    failed = {k: v["error"] for k, v in rows.items() if "error" in v}
    done = [v for v in rows.values() if "error" not in v]
    seconds = time.perf_counter() - t0
    print(f"{len(done)} of {len(files)} sketches: {sum(v['strokes_in'] for v in done)} strokes "
          f"-> {sum(v['strokes_out'] for v in done)} in {seconds:.2f} s with {jobs} job(s)")
    for name, error in failed.items():
        print(f"  failed {name}: {error}")
    if summary is not None:
        summary.write_text(json.dumps({"files": rows, "seconds": seconds, "jobs": jobs,
                                       "params": params.as_dict()}, indent=2))
    return 1 if failed else 0
