"""Reading SVG drawings into sketches and writing sketches as SVG.

Parsing is svgelements' (every path command, shapes, nested transforms, units); this module
only turns its segments into polylines, sampling curves adaptively so that no chord strays
more than ``tolerance`` from the curve. defusedxml screens the document first, so entity
expansion and external entities are refused before svgelements sees the file.
"""

from __future__ import annotations

import io
import math
import re
from pathlib import Path
from xml.etree.ElementTree import ParseError

import defusedxml.ElementTree as safe_et
import numpy as np
import svgelements as se
from defusedxml import DefusedXmlException

from ..sketch import Sketch, SketchError, Stroke

__all__ = [
    "MAX_SVG_BYTES", "MAX_SVG_ELEMENTS", "MAX_SVG_NUMBERS", "RELATIVE_TOLERANCE", "format_svg",
    "parse_svg", "path_data", "read_svg", "write_svg",
]

#: default sampling tolerance, as a fraction of the drawing's bounding-box diagonal
RELATIVE_TOLERANCE = 5e-4
#: largest SVG file read, in bytes
MAX_SVG_BYTES = 64 * 1024 * 1024
#: most elements after every <use> is expanded: a few <use> can stand for billions
MAX_SVG_ELEMENTS = 100_000
_XLINK_HREF = "{http://www.w3.org/1999/xlink}href"
#: most digit groups in all path data and point lists together (a number has one or two):
#: about 250,000 points, which svgelements reads in some seconds and a few hundred MB
MAX_SVG_NUMBERS = 1_000_000
_DIGIT_GROUP = re.compile(r"[0-9]+")


def _cubic_steps(p: np.ndarray, tol: float) -> int:
    """Uniform steps that keep a cubic within ``tol`` of its chords (second-difference bound)."""
    d2 = max(np.hypot(*(p[0] - 2 * p[1] + p[2])), np.hypot(*(p[1] - 2 * p[2] + p[3])))
    return max(1, math.ceil(math.sqrt(6.0 * d2 / (8.0 * tol))))


def _segment_steps(seg: se.PathSegment, tol: float) -> int:
    if isinstance(seg, se.CubicBezier):
        pts = np.array([seg.start, seg.control1, seg.control2, seg.end], dtype=float)
        return _cubic_steps(pts, tol)
    if isinstance(seg, se.QuadraticBezier):
        d2 = np.hypot(*(np.array(seg.start) - 2 * np.array(seg.control) + np.array(seg.end)))
        return max(1, math.ceil(math.sqrt(2.0 * d2 / (8.0 * tol))))
    if isinstance(seg, se.Arc):
        radius = max(abs(seg.rx), abs(seg.ry), tol)
        step = 2.0 * math.acos(max(1.0 - tol / radius, -1.0))
        return max(1, math.ceil(abs(seg.sweep) / max(step, 1e-9)))
    return 1


def _subpath_polyline(subpath: se.Subpath, tol: float) -> tuple[np.ndarray, bool]:
    pieces: list[np.ndarray] = []
    closed = False
    for seg in subpath:
        if isinstance(seg, se.Move):
            pieces.append(np.array([seg.end], dtype=float))
        elif isinstance(seg, (se.Line, se.Close)):
            if seg.start is None or seg.end is None:
                continue
            if not pieces:
                pieces.append(np.array([seg.start], dtype=float))
            pieces.append(np.array([seg.end], dtype=float))
            closed = closed or isinstance(seg, se.Close)
        else:
            n = _segment_steps(seg, tol)
            pts = np.asarray(seg.npoint(np.linspace(0.0, 1.0, n + 1)), dtype=float)
            if not pieces:
                pieces.append(pts[:1])
            pieces.append(pts[1:])
    if not pieces:
        return np.empty((0, 2)), False
    return np.concatenate(pieces), closed


class _NoPath:
    """Receives a path's commands and keeps none: the lexer is run only to check them."""
    current_point = None

    def __getattr__(self, name: str):
        return lambda *args, **kwargs: None


def _check_path_data(d: str, where: str) -> None:
    """Refuse path data that svgelements would read only in part.

    Like a browser, svgelements stops quietly at the first error and keeps what came
    before; a sketch would then lose strokes without a word. Its own lexer is run here and
    must reach the end of the data.
    """
    lexer = se.SVGLexicalParser()
    try:
        lexer.parse(_NoPath(), d)
        ok = not d[lexer.pos:].strip(" \t\r\n,")
    except (ValueError, TypeError):
        ok = False
    if not ok:
        near = d[lexer.pos:lexer.pos + 20]
        raise SketchError(f"{where}: malformed path data at character {lexer.pos} "
                          f"(near {near!r})")


def _more_numbers_than(limit: int, texts) -> bool:
    """Whether the texts hold more than ``limit`` digit groups; counted lazily and given up
    at the limit, so a hostile file costs no more than a legitimate one."""
    count = 0
    for text in texts:
        for _ in _DIGIT_GROUP.finditer(text):
            count += 1
            if count > limit:
                return True
    return False


def _local_name(element) -> str:
    """An element's tag without its namespace: 'path' for '{http://...svg}path'."""
    return element.tag.rsplit("}", 1)[-1]


def _expanded_size(root, limit: int, name: str) -> int:
    """How many elements the document has once every ``<use>`` is replaced by what it
    refers to (counted up to ``limit`` + 1), refusing references that loop."""
    ids = {e.get("id"): e for e in root.iter() if e.get("id")}

    def kids(e) -> list:
        href = e.get(_XLINK_HREF) or e.get("href") or ""
        ref = ids.get(href[1:]) if _local_name(e) == "use" and href[:1] == "#" else None
        return list(e) + ([ref] if ref is not None else [])

    size: dict[int, int] = {}
    on_path: set[int] = set()
    stack = [(root, False)]
    while stack:  # post-order without recursion: documents may nest deeply
        e, done = stack.pop()
        if done:
            on_path.discard(id(e))
            size[id(e)] = min(1 + sum(size[id(k)] for k in kids(e)), limit + 1)
        elif id(e) in on_path:
            raise SketchError(f"{name}: a <use> refers to an element that contains it")
        elif id(e) not in size:
            on_path.add(id(e))
            stack.append((e, True))
            stack.extend((k, False) for k in kids(e) if id(k) not in size)
    return size[id(root)]


def _screen(data: bytes, name: str) -> None:
    """Refuse what the SVG library should never see: unsafe or malformed XML, more
    geometry than can be read in bounded time and memory, malformed path data."""
    try:
        root = safe_et.fromstring(data, forbid_dtd=False, forbid_entities=True,
                                  forbid_external=True)
    except DefusedXmlException as exc:
        raise SketchError(f"{name}: refused unsafe XML ({type(exc).__name__})") from None
    except ParseError as exc:
        raise SketchError(f"{name}: not well-formed XML ({exc})") from None
    if _expanded_size(root, MAX_SVG_ELEMENTS, name) > MAX_SVG_ELEMENTS:
        raise SketchError(f"{name}: more than {MAX_SVG_ELEMENTS} elements once <use> "
                          "references are expanded")
    geometry = [(e, e.get("d"), e.get("points")) for e in root.iter()]
    if _more_numbers_than(MAX_SVG_NUMBERS, (v for _, d, pts in geometry for v in (d, pts) if v)):
        raise SketchError(f"{name}: too much path data (more than {MAX_SVG_NUMBERS} numbers)")
    for element, d, _ in geometry:
        if d is not None and _local_name(element) == "path":
            _check_path_data(d, f"{name}: path {element.get('id') or ''}".rstrip())


def _style(shape: se.Shape) -> str | None:
    colour = shape.stroke if shape.stroke is not None and shape.stroke.value is not None else None
    return colour.hex if colour is not None else None


def parse_svg(data: bytes, name: str = "<svg>", tolerance: float | None = None) -> Sketch:
    """Parse SVG bytes. Each subpath of each shape becomes one stroke.

    ``tolerance`` is the largest distance between a sampled polyline and its curve, in the
    document's user units; by default :data:`RELATIVE_TOLERANCE` of the drawing's diagonal.
    """
    if len(data) > MAX_SVG_BYTES:
        raise SketchError(f"{name}: {len(data)} bytes is larger than the {MAX_SVG_BYTES} read")
    _screen(data, name)
    try:
        document = se.SVG.parse(io.BytesIO(data))
    except Exception as exc:  # svgelements raises bare ValueError/IndexError on bad data
        raise SketchError(f"{name}: unreadable SVG ({type(exc).__name__}: {exc})") from None
    shapes = [e for e in document.elements() if isinstance(e, se.Shape)]
    paths = []
    for shape in shapes:
        try:
            paths.append((shape, shape if isinstance(shape, se.Path) else se.Path(shape)))
        except Exception as exc:
            raise SketchError(f"{name}: cannot read shape {shape.id!r} ({exc})") from None
    boxes = np.array([b for _, p in paths if (b := p.bbox()) is not None], dtype=float)
    if len(boxes) == 0:
        raise SketchError(f"{name}: no drawable paths or shapes")
    if tolerance is None:
        with np.errstate(over="ignore", invalid="ignore"):
            span = np.hypot(boxes[:, 2].max() - boxes[:, 0].min(),
                            boxes[:, 3].max() - boxes[:, 1].min())
        if not np.isfinite(span):
            raise SketchError(f"{name}: coordinates too large to draw (extent {span})")
        tolerance = RELATIVE_TOLERANCE * span if span > 0 else 1.0
    if not tolerance > 0:
        raise SketchError(f"sampling tolerance must be positive, got {tolerance}")
    strokes = []
    for shape, path in paths:
        width = shape.stroke_width if shape.stroke_width is not None else None
        for subpath in path.as_subpaths():
            pts, closed = _subpath_polyline(subpath, tolerance)
            if len(pts) == 0:
                continue
            strokes.append(Stroke(pts, width=None if width is None else float(width),
                                  style=_style(shape), source_id=len(strokes), closed=closed))
    if not strokes:
        raise SketchError(f"{name}: no drawable paths or shapes")
    width = float(document.width) if document.width else None
    height = float(document.height) if document.height else None
    return Sketch(strokes, width, height)


def read_svg(path: str | Path, tolerance: float | None = None) -> Sketch:
    path = Path(path)
    return parse_svg(path.read_bytes(), str(path), tolerance)


def _fmt(v: float) -> str:
    return f"{v:.9g}"


def path_data(stroke: Stroke) -> str:
    """SVG path data: cubic ``C`` segments for a Bezier stroke, ``L`` otherwise."""
    if stroke.bezier is not None:
        b = stroke.bezier
        head = f"M{_fmt(b[0, 0])} {_fmt(b[0, 1])}"
        rest = " ".join(
            "C" + " ".join(f"{_fmt(x)} {_fmt(y)}" for x, y in b[i:i + 3])
            for i in range(1, len(b), 3)
        )
    else:
        p = stroke.points
        head = f"M{_fmt(p[0, 0])} {_fmt(p[0, 1])}"
        rest = "L" + " ".join(f"{_fmt(x)} {_fmt(y)}" for x, y in p[1:])
    return f"{head} {rest}" + (" Z" if stroke.closed else "")


def format_svg(sketch: Sketch, stroke_width: float | None = None) -> str:
    """An SVG document with one ``<path>`` per stroke, in the sketch's own coordinates."""
    x0, y0, x1, y1 = sketch.bounds()
    if sketch.width and sketch.height:
        x0, y0 = min(x0, 0.0), min(y0, 0.0)
        x1, y1 = max(x1, sketch.width), max(y1, sketch.height)
    w, h = max(x1 - x0, 1e-12), max(y1 - y0, 1e-12)
    default_width = stroke_width if stroke_width is not None else max(w, h) / 500.0
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{_fmt(x0)} {_fmt(y0)} {_fmt(w)} '
        f'{_fmt(h)}" width="{_fmt(w)}" height="{_fmt(h)}">',
        '<g fill="none" stroke-linecap="round" stroke-linejoin="round">',
    ]
    for s in sketch.strokes:
        colour = s.style if s.style and s.style.startswith("#") else "#000000"
        width = float(np.mean(s.width)) if s.width is not None else default_width
        lines.append(f'<path d="{path_data(s)}" stroke="{colour}" stroke-width="{_fmt(width)}"/>')
    lines += ["</g>", "</svg>"]
    return "\n".join(lines) + "\n"


def write_svg(sketch: Sketch, path: str | Path, stroke_width: float | None = None) -> None:
    Path(path).write_text(format_svg(sketch, stroke_width), encoding="utf-8")
