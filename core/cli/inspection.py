"""``python -m core inspect``: what a sketch's base complex is made of."""

from __future__ import annotations

import json
import time
from pathlib import Path

from ..complex.base_complex import build_base_complex
from ..io.cleaning import clean_sketch, normalised_strokes
from ..io.files import read_sketch

__all__ = ["format_inspection", "inspect_sketch", "run"]


def inspect_sketch(path: str | Path) -> dict:
    """Counts of the sketch and its base complex, and the seconds each stage took."""
    t0 = time.perf_counter()
    raw = read_sketch(path)
    t_read = time.perf_counter() - t0
    sketch, report = clean_sketch(raw)
    strokes, norm = normalised_strokes(sketch)
    cx = build_base_complex(strokes)
    clusters = {s.cluster for s in sketch.strokes if s.cluster is not None}
    return {
        "file": str(path),
        "strokes": len(raw.strokes),
        "points": raw.num_points,
        "clusters": len(clusters) or None,
        "cleaning": report.as_dict(),
        "diagonal": norm.scale,
        **cx.summary(),
        "read_seconds": round(t_read, 6),
    }


def format_inspection(info: dict) -> str:
    c = info["cleaning"]
    dropped = c["strokes_in"] - c["strokes_out"]
    lines = [
        f"{info['file']}",
        f"  strokes     {info['strokes']} ({info['points']} points"
        + (f", {info['clusters']} clusters" if info["clusters"] else "")
        + (f", {dropped} dropped" if dropped else "") + ")",
        f"  nodes       {info['nodes']}",
        f"  curves      {info['curves']}",
        f"  patches     {info['patches']}",
        f"  components  {info['components']}",
        f"  seconds     {info['seconds']:.4f} (base complex), {info['read_seconds']:.4f} (read)",
    ]
    return "\n".join(lines)


def run(paths: list[str], as_json: bool) -> None:
    infos = [inspect_sketch(p) for p in paths]
    if as_json:
        print(json.dumps(infos[0] if len(infos) == 1 else infos, indent=2))
    else:
        print("\n".join(format_inspection(i) for i in infos))
