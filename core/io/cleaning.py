"""Cleaning raw strokes, and the frame the pipeline works in: the drawing's own box
(the strokes' bounding box unless some ink lies far away) at unit diagonal."""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import shapely

from ..arrays.polylines import end_to_end, total_lengths
from ..sketch import Sketch, SketchError, Stroke

__all__ = [
    "DRAWING_REACH", "MAX_INK_DIAGONALS", "MIN_STROKE_SHARE", "PARTS_APART", "clean_sketch",
    "clean_stroke", "CleaningReport", "drawing_box", "drawing_part_areas", "drawing_parts",
    "drawing_strokes",
    "Normalisation", "normalised_strokes",
]


@dataclass
class CleaningReport:
    """What :func:`clean_sketch` removed."""

    strokes_in: int
    strokes_out: int
    nonfinite_points: int
    duplicate_points: int
    degenerate_strokes: int

    def as_dict(self) -> dict[str, int]:
        return asdict(self)


def clean_stroke(stroke: Stroke) -> tuple[Stroke | None, int, int]:
    """Drop non-finite points and consecutive duplicates.

    Returns the cleaned stroke (None when fewer than 2 distinct points remain), the number
    of non-finite points and the number of duplicate points removed.
    """
    pts = stroke.points
    finite = np.isfinite(pts).all(axis=1)
    keep = np.flatnonzero(finite)
    kept = pts[keep]
    distinct = np.ones(len(kept), dtype=bool)
    distinct[1:] = (kept[1:] != kept[:-1]).any(axis=1)
    keep = keep[distinct]
    nonfinite = int(len(pts) - finite.sum())
    duplicates = int(len(kept) - distinct.sum())
    if len(keep) < 2:
        return None, nonfinite, duplicates
    if nonfinite == 0 and duplicates == 0:
        return stroke, 0, 0
    return stroke.with_points(pts[keep], keep), nonfinite, duplicates


def clean_sketch(sketch: Sketch) -> tuple[Sketch, CleaningReport]:
    """Remove what cannot be drawn; raise :class:`SketchError` if nothing drawable is left."""
    if not isinstance(sketch, Sketch):
        raise SketchError(f"expected a Sketch, got {type(sketch).__name__}")
    if len(sketch.strokes) == 0:
        raise SketchError("the sketch has no strokes")
    out: list[Stroke] = []
    nonfinite = duplicates = degenerate = 0
    for stroke in sketch.strokes:
        cleaned, nf, dup = clean_stroke(stroke)
        nonfinite += nf
        duplicates += dup
        if cleaned is None:
            degenerate += 1
        else:
            out.append(cleaned)
    if not out:
        raise SketchError(
            f"none of the {len(sketch.strokes)} strokes has two distinct finite points"
        )
    report = CleaningReport(len(sketch.strokes), len(out), nonfinite, duplicates, degenerate)
    return Sketch(out, sketch.width, sketch.height), report


#: extents whose squares still are normal floating-point numbers
MIN_EXTENT, MAX_EXTENT = 1e-150, 1e150


@dataclass(frozen=True)
class Normalisation:
    """Maps sketch coordinates to the drawing's frame and back: the drawing's box (all the
    strokes' bounding box unless some ink lies far from the drawing, :func:`drawing_box`)
    has its corner at 0 and diagonal 1. The drawing's strokes get the same coordinates
    there, to the bit, whatever ink lies far away."""

    origin: tuple[float, float]
    scale: float
    #: the drawing's box in this frame, (0, 0) to its far corner: ink outside lies far
    box: tuple[float, float, float, float]

    @classmethod
    def of(cls, sketch: Sketch) -> Normalisation:
        x0, y0, x1, y1 = sketch.bounds()
        diag = float(np.hypot(x1 - x0, y1 - y0))
        if not np.isfinite(diag) or diag <= 0.0:
            raise SketchError("the sketch has zero extent: every point is the same")
        if not MIN_EXTENT <= diag <= MAX_EXTENT:
            raise SketchError(f"the sketch's extent {diag:.3g} is outside {MIN_EXTENT:.0e} to "
                              f"{MAX_EXTENT:.0e}, where distances cannot be measured")
        x0, y0, x1, y1 = drawing_box([s.points for s in sketch.strokes]).tolist()
        drawing = float(np.hypot(x1 - x0, y1 - y0))
        if not drawing >= MIN_EXTENT:
            raise SketchError(f"the drawing's extent {drawing:.3g} is below {MIN_EXTENT:.0e} "
                              "beside ink far away, where distances cannot be measured")
        _check_resolvable(sketch, drawing)
        return cls((x0, y0), drawing, (0.0, 0.0, (x1 - x0) / drawing, (y1 - y0) / drawing))

    def to_unit(self, points: np.ndarray) -> np.ndarray:
        return (points - np.asarray(self.origin)) / self.scale

    def from_unit(self, points: np.ndarray) -> np.ndarray:
        return points * self.scale + np.asarray(self.origin)


#: the ink may be at most this many times as long as the drawing's diagonal: it is sampled
#: a few hundred times a diagonal (a quarter of d_eps), so 10,000 diagonals are a few
#: million samples; a 5,000-stroke page holds about a thousand. Beyond it lies ink far
#: from the drawing (a line a million diagonals long beside it), not a drawing
MAX_INK_DIAGONALS = 1e4
#: the largest stroke must be at least this share of the drawing's diagonal: a hundred
#: times the grid the complex's noding snaps to (:data:`core.complex.noding.GRID`), where
#: every stroke would collapse, and nothing come out
MIN_STROKE_SHARE = 1e-4


def _check_resolvable(sketch: Sketch, drawing: float) -> None:
    """Refuse, with a message that says why, a sketch whose ink the drawing's scale cannot
    hold: far too long (memory), or every stroke far too small (nothing would come out)."""
    ink = largest = 0.0
    for s in sketch.strokes:
        ink += float(np.hypot(*np.diff(s.points, axis=0).T).sum())
        largest = max(largest, float(np.hypot(*np.ptp(s.points, axis=0))))
    if ink > MAX_INK_DIAGONALS * drawing:
        raise SketchError(f"the ink is {ink / drawing:.3g} times as long as the drawing's "
                          f"diagonal ({drawing:.3g}), more than {MAX_INK_DIAGONALS:.0e}: ink far "
                          "from the drawing is too long to simplify at its scale (simplify "
                          "the parts apart)")
    if largest < MIN_STROKE_SHARE * drawing:
        raise SketchError(f"every stroke is under {MIN_STROKE_SHARE:.0e} of the drawing's "
                          f"diagonal ({drawing:.3g}; the largest is {largest:.3g} across): "
                          "parts this far apart cannot be simplified as one drawing "
                          "(simplify the parts apart)")


def normalised_strokes(sketch: Sketch) -> tuple[list[np.ndarray], Normalisation]:
    """The stroke polylines of a cleaned sketch in the drawing's unit-diagonal frame."""
    norm = Normalisation.of(sketch)
    return [norm.to_unit(s.points) for s in sketch.strokes], norm


#: a stroke whose box comes within this fraction of the drawing's diagonal of the drawing
#: belongs to it (drawing_box): the letters of a word, a detached part of a product
#: sketch, are one drawing. decisions: "The drawing's frame"
DRAWING_REACH = 0.25

#: parts of the ink separated by a gap wider than this many times the median stroke's
#: length are separate drawings (drawing_parts): the hand lifted and moved on, no stroke
#: drawn across the gap. Scale-free, from the pen, not the page. decisions: "The
#: drawing's frame"
PARTS_APART = 1.0


def _boxes_and_lengths(strokes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Each stroke's box (x0, y0, x1, y1) and length, over all strokes at once."""
    points, first, _ = end_to_end(strokes)
    boxes = np.hstack([np.minimum.reduceat(points, first), np.maximum.reduceat(points, first)])
    return boxes, total_lengths(strokes)


def drawing_parts(strokes: list[np.ndarray]) -> np.ndarray:
    """A label per stroke: its drawing, where ink separated by a gap wider than
    :data:`PARTS_APART` times the median stroke's length is two drawings (the strokes' boxes
    chained while they come that close in x and in y). Labels are numbered in the order
    of their first strokes. Memory grows with the strokes, not with the pairs of them
    that come close (a dense drawing's strokes all do): the boxes, each grown by half the
    gap, are united by GEOS, and each stroke takes the part that holds its box.

    >>> t = np.linspace(0, 1, 50)[:, None]
    >>> cross = [np.hstack([t, t]), np.hstack([t, 1 - t])]
    >>> drawing_parts(cross + [s + [3.0, 0.0] for s in cross]).tolist()  # two crosses
    [0, 0, 1, 1]
    >>> drawing_parts(cross + [s + [1.5, 0.0] for s in cross]).tolist()  # 0.5 apart
    [0, 0, 0, 0]
    """
    return _parts(*_boxes_and_lengths(strokes))[0]


def drawing_part_areas(strokes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """:func:`drawing_parts`' labels, and each part's area (shapely polygons, by label):
    disjoint, each holding its strokes whole, so that whatever lies on a stroke (a curve
    of the complex) is found in its part's area.

    >>> t = np.linspace(0, 1, 50)[:, None]
    >>> cross = [np.hstack([t, t]), np.hstack([t, 1 - t])]
    >>> labels, areas = drawing_part_areas(cross + [s + [3.0, 0.0] for s in cross])
    >>> labels.tolist(), [round(a.centroid.x, 6) for a in areas]
    ([0, 0, 1, 1], [0.5, 3.5])
    """
    return _parts(*_boxes_and_lengths(strokes))


def _parts(boxes: np.ndarray, lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    half = 0.5 * PARTS_APART * float(np.median(lengths))
    label = np.zeros(len(boxes), dtype=np.intp)
    everything = np.array([shapely.box(*boxes[:, :2].min(axis=0), *boxes[:, 2:].max(axis=0))]
                          if len(boxes) else [], dtype=object)
    if not half > 0:  # most strokes points: no length to judge a gap by
        return label, everything
    grown = shapely.box(*(boxes[:, :2] - half).T, *(boxes[:, 2:] + half).T)
    parts = shapely.get_parts(shapely.union_all(grown))
    if len(parts) <= 1:
        return label, np.array([shapely.union_all(grown)], dtype=object)
    centres = shapely.points(0.5 * (boxes[:, :2] + boxes[:, 2:]))
    stroke, part = shapely.STRtree(parts).query(centres, predicate="intersects")
    label[stroke] = part
    _, first, inverse = np.unique(label, return_index=True, return_inverse=True)
    order = np.argsort(first)  # parts by their first strokes
    return np.argsort(order)[inverse].astype(np.intp), parts[np.unique(label)[order]]


def _main_part(labels: np.ndarray, lengths: np.ndarray) -> int:
    """The part that holds the most ink (the first of equal ones: the copies of one
    drawing on a page hold the same, to rounding). Ink, not strokes: then no other part
    is longer to sample than it, and a page costs at most its number of parts times the
    main one (counted by strokes, two scraps outnumbered a drawing of one stroke, and a
    line 6,000 of a small drawing's diagonals long far from it took minutes)."""
    ink = np.bincount(labels, weights=lengths)
    return int(np.flatnonzero(ink >= ink.max() * (1 - 1e-9))[0])


def drawing_box(strokes: list[np.ndarray]) -> np.ndarray:
    """The box (x0, y0, x1, y1) of the drawing that holds the bulk of the ink: the strokes'
    bounding box, exactly, when they are one drawing.

    Lengths that decide what merges follow the drawing, not the canvas or the page: one
    stray mark ten diagonals away must not make the drawing's bundles ten times narrower,
    and a page of drawings must give each the bundles it gets alone. So the drawing is
    first the part of the ink (:func:`drawing_parts`) that holds the most of it
    (:func:`_main_part`): on a page of copies of one drawing, or of drawings of one size,
    each gets its own width; of a drawing and scraps apart, the drawing's; of parts of
    many sizes, the main one's, at most the whole page's as before (docs/decisions.md:
    the part half the ink is drawn at was measured too). Within it,
    the drawing grows from the strokes crossing the middle of its ink (the box between the
    quartiles of the stroke points in x and in y) by every stroke whose box comes within
    ``DRAWING_REACH`` times the drawing's diagonal, until none does. A stroke left out lies far
    from all of it (why from the middle box, not one stroke: "The drawing's frame").

    >>> t = np.linspace(0, 1, 50)[:, None]
    >>> cross = [np.hstack([t, t]), np.hstack([t, 1 - t])]
    >>> drawing_box(cross).tolist()
    [0.0, 0.0, 1.0, 1.0]
    >>> drawing_box(cross + [np.array([[30., 30], [30.1, 30]])]).tolist()
    [0.0, 0.0, 1.0, 1.0]
    >>> drawing_box(cross + [s + [3.0, 0.0] for s in cross]).tolist()  # a page of two
    [0.0, 0.0, 1.0, 1.0]
    """
    boxes, lengths = _boxes_and_lengths(strokes)
    labels = _parts(boxes, lengths)[0]
    if labels.max() > 0:
        mine = labels == _main_part(labels, lengths)
        strokes, boxes = [s for s, m in zip(strokes, mine.tolist()) if m], boxes[mine]
    points = np.concatenate(strokes)
    region = np.concatenate([np.percentile(points, 25, axis=0),
                             np.percentile(points, 75, axis=0)])
    member = np.zeros(len(boxes), bool)
    while True:
        margin = DRAWING_REACH * float(np.hypot(*(region[2:] - region[:2])))
        near = ((boxes[:, 0] <= region[2] + margin) & (boxes[:, 2] >= region[0] - margin)
                & (boxes[:, 1] <= region[3] + margin) & (boxes[:, 3] >= region[1] - margin))
        if not (near & ~member).any():
            break
        member |= near
        region = np.concatenate([boxes[member, :2].min(axis=0), boxes[member, 2:].max(axis=0)])
    return region


def drawing_strokes(unit_strokes: list[np.ndarray],
                    box: tuple[float, float, float, float] | None = None) -> list[np.ndarray]:
    """The strokes of the drawing (:func:`drawing_box`, or ``box``: the frame's own,
    :attr:`Normalisation.box`, found once) in the unit frame: ink far away left out, so
    that what is measured of the drawing's ink (its spacing, its strokes' lengths) is the
    drawing's alone.

    >>> t = np.linspace(0, 1, 50)[:, None]
    >>> cross = [np.hstack([t, t]), np.hstack([t, 1 - t])]
    >>> len(drawing_strokes(cross + [np.array([[30., 30], [30.1, 30]])]))
    2
    """
    x0, y0, x1, y1 = drawing_box(unit_strokes).tolist() if box is None else box
    tol = 1e-9 * max(1.0, abs(x0), abs(y0), abs(x1), abs(y1))
    return [u for u in unit_strokes
            if u[:, 0].min() >= x0 - tol and u[:, 0].max() <= x1 + tol
            and u[:, 1].min() >= y0 - tol and u[:, 1].max() <= y1 + tol]
