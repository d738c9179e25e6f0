"""Reading and writing the ``.scap`` stroke format of the StrokeAggregator family of tools.

Format (text)::

    #<canvas width> <canvas height>
    @<default thickness>
    {
        #<stroke id> <cluster id>
        @<thickness>            (optional)
        <x> <y> <pressure>      one point a line
    }
    #<old id> [a, b) --> #<new id>     (records of cut strokes; skipped)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..sketch import Sketch, SketchError, Stroke

__all__ = ["format_scap", "parse_scap", "read_scap", "write_scap"]


def _numbers(text: str, where: str) -> list[float]:
    try:
        return [float(v) for v in text.split()]
    except ValueError:
        raise SketchError(f"{where}: expected numbers, got {text.strip()[:60]!r}") from None


def parse_scap(text: str, name: str = "<scap>") -> Sketch:
    """Parse ``.scap`` text. Cluster ids are kept in :attr:`Stroke.cluster`."""
    width = height = None
    default_thickness: float | None = None
    strokes: list[Stroke] = []
    block: list[str] | None = None
    header: tuple[int | None, int | None, float | None] = (None, None, None)
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line:
            continue
        where = f"{name}:{lineno}"
        if block is None:
            if line == "{":
                block, header = [], (None, None, default_thickness)
            elif line.startswith("#") and "-->" not in line and width is None and not strokes:
                vals = _numbers(line[1:], where)
                if len(vals) >= 2:
                    width, height = vals[0], vals[1]
            elif line.startswith("@"):
                vals = _numbers(line[1:], where)
                default_thickness = vals[0] if vals else None
            elif line.startswith("#") or line == "}":
                continue  # cut-stroke records and stray closers carry no geometry
            else:
                raise SketchError(f"{where}: unexpected text outside a stroke block: {line[:60]!r}")
        elif line == "}":
            strokes.append(_stroke_from_block(block, header, where))
            block = None
        elif line.startswith("#"):
            vals = _numbers(line[1:], where)
            sid = int(vals[0]) if vals else None
            cluster = int(vals[1]) if len(vals) > 1 else None
            header = (sid, cluster, header[2])
        elif line.startswith("@"):
            vals = _numbers(line[1:], where)
            header = (header[0], header[1], vals[0] if vals else header[2])
        else:
            block.append(line)
    if block is not None:
        raise SketchError(f"{name}: the last stroke block is not closed with '}}'")
    if not strokes:
        raise SketchError(f"{name}: no strokes found")
    return Sketch(strokes, width, height)


def _stroke_from_block(lines: list[str], header: tuple, where: str) -> Stroke:
    sid, cluster, thickness = header
    if not lines:
        return Stroke(np.empty((0, 2)), source_id=sid, cluster=cluster)
    values = np.array(_numbers(" ".join(lines), where))
    cols = len(lines[0].split())
    if cols < 2 or len(values) != cols * len(lines):
        raise SketchError(f"{where}: stroke {sid} has rows of unequal length")
    table = values.reshape(len(lines), cols)
    pressure = table[:, 2] if cols >= 3 else None
    width = None if thickness is None else np.full(len(table), thickness)
    return Stroke(table[:, :2], width=width, pressure=pressure, source_id=sid, cluster=cluster)


def read_scap(path: str | Path) -> Sketch:
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="strict")
    except UnicodeDecodeError as exc:
        raise SketchError(f"{path}: not a text file ({exc.reason})") from None
    return parse_scap(text, str(path))


def format_scap(sketch: Sketch, default_thickness: float = 1.0) -> str:
    """The ``.scap`` text of a sketch; ids default to the stroke index, clusters to it too."""
    if sketch.width is not None and sketch.height is not None:
        w, h = sketch.width, sketch.height
    else:
        x0, y0, x1, y1 = sketch.bounds()
        w, h = x1, y1
    out = [f"#{w:g}\t{h:g}", f"@{default_thickness:g}"]
    for i, s in enumerate(sketch.strokes):
        sid = s.source_id if s.source_id is not None else i
        cluster = s.cluster if s.cluster is not None else i
        out += ["{", f"\t#{sid}\t{cluster}"]
        if s.width is not None and len(s.width):
            out.append(f"\t@{float(np.mean(s.width)):g}")
        pressure = s.pressure if s.pressure is not None else np.zeros(len(s))
        out += [f"\t{x:.9g}\t{y:.9g}\t{p:.9g}" for (x, y), p in zip(s.points, pressure)]
        out.append("}")
    return "\n".join(out) + "\n"


def write_scap(sketch: Sketch, path: str | Path) -> None:
    Path(path).write_text(format_scap(sketch), encoding="utf-8")
