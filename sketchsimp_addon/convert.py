"""Between Grease Pencil drawings and the core's plain sketches.

Strokes live in 3D layer space; the core works in 2D. Each drawing is projected onto its
own best-fit plane (the two main axes of its points: the X-Z plane for a front-view
drawing) and the result is lifted back onto the same plane, so no transform is involved.
Width comes from the stroke radius; material, opacity and vertex colour of an output
stroke come from the input strokes it was made from, per knot from the nearest of their
points (colour from those of the stroke's main colour, where that colour's ink lies within
the bundle width of the knot).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace

import numpy as np
import shapely

from ..core import SAMPLES_PER_SEGMENT, Region, Sketch, SketchError, Stroke, subdivide_bezier
from .drawing import DrawingData, NewStrokes

__all__ = [
    "FAR_OUT", "FILL_RADIUS", "KNOTS_PER_SEGMENT", "Plane", "drawing_from_polylines",
    "drawing_plane", "far_out", "fill_strokes", "stroke_moved", "to_new_strokes", "to_sketch",
]


@dataclass(frozen=True)
class Plane:
    centre: np.ndarray  # (3,)
    axes: np.ndarray  # (2, 3), orthonormal

    def to_2d(self, points: np.ndarray) -> np.ndarray:
        return (points - self.centre) @ self.axes.T

    def to_3d(self, points: np.ndarray) -> np.ndarray:
        return (self.centre + points @ self.axes).astype(np.float32)

    def moved_from(self, other: Plane, points: np.ndarray) -> np.ndarray:
        """2D points of ``other`` plane, in this plane's 2D frame (in full precision)."""
        return self.to_2d(other.centre + np.asarray(points, np.float64) @ other.axes)

    def off_plane(self, points: np.ndarray) -> float:
        """How far the points farthest from the plane are from it (what flattening onto
        it moves them by); non-finite points are left out."""
        pts = np.asarray(points, dtype=np.float64)
        pts = pts[np.isfinite(pts).all(axis=1)]
        normal = np.cross(self.axes[0], self.axes[1])
        return float(np.abs((pts - self.centre) @ normal).max()) if len(pts) else 0.0


def drawing_plane(positions: np.ndarray) -> Plane:
    """The plane through the points' centre that fits them best, with its in-plane axes
    aligned to the layer's X axis and "up" (Z, or Y for a top view) rather than to the
    points' own main directions: those turn with the ink (a square drawing's are at any
    angle, and a stray mark swings them round), and the simplification is measured in
    this frame. A front-view drawing gets the X-Z plane exactly.

    Non-finite points (a NaN from a broken import) are left out; the core drops them."""
    pts = np.asarray(positions, dtype=np.float64)
    pts = pts[np.isfinite(pts).all(axis=1)]
    if len(pts) == 0:
        raise SketchError("no point has finite coordinates")
    centre = pts.mean(axis=0)
    # the thin SVD: (n, 3) and 3 x 3 factors, memory and time linear in the points (the
    # full one built an n x n matrix: 640 GiB for a 5,000-stroke layer)
    _, sv, vt = np.linalg.svd(pts - centre, full_matrices=False)
    if len(sv) < 2 or sv[0] <= 1e-300:
        return Plane(centre, np.array([[1.0, 0, 0], [0, 0, 1.0]]))  # one point: X-Z
    if sv[1] <= 1e-12 * sv[0]:  # on one line: any plane through it, the most upright
        direction = vt[0]
        normal = np.cross(direction, [0.0, 0, 1] if abs(direction[2]) < 0.9 else [0.0, 1, 0])
        normal /= np.linalg.norm(normal)
    else:
        normal = vt[2]
    first = None
    for axis in np.eye(3):  # X, then Y, then Z: the first that lies in the plane enough
        along = axis - normal * (normal @ axis)
        if np.linalg.norm(along) > 0.3:
            first = along / np.linalg.norm(along)
            break
    second = np.cross(normal, first)
    up = np.array([0.0, 0, 1]) if abs(second[2]) > 1e-9 else np.array([0.0, 1, 0])
    if second @ up < 0:
        second = -second
    return Plane(centre, np.stack([first, second]))


#: a point farther than this many times the drawing's size from the middle of its ink is
#: broken data (a stray 1e30 from a bad import), not a stroke: it is left out as a NaN is
FAR_OUT = 1000.0


def far_out(positions: np.ndarray) -> np.ndarray:
    """Which points are broken data, far outside the drawing (see ``FAR_OUT``): measured
    from the median point against the box of the middle 98% of the points, so that a few
    such points cannot stretch the measure."""
    pts = np.asarray(positions, dtype=np.float64)
    finite = np.isfinite(pts).all(axis=1)
    out = np.zeros(len(pts), dtype=bool)
    if finite.sum() < 2:
        return out
    inner = pts[finite]
    size = float(np.linalg.norm(np.percentile(inner, 99, axis=0)
                                - np.percentile(inner, 1, axis=0)))
    if not size > 0:
        return out
    offset = np.linalg.norm(inner - np.median(inner, axis=0), axis=1)
    out[np.flatnonzero(finite)] = offset > FAR_OUT * size
    return out


def drawing_from_polylines(polylines: list[np.ndarray], closed: list[bool]) -> DrawingData:
    """Curve-object splines dressed as a drawing, with Grease Pencil's default attributes."""
    counts = [len(p) for p in polylines]
    n = sum(counts)
    return DrawingData(
        positions=np.concatenate(polylines).astype(np.float32),
        offsets=np.concatenate([[0], np.cumsum(counts)]).astype(np.int32),
        radius=np.full(n, 0.01, np.float32), opacity=np.ones(n, np.float32),
        vertex_color=None, material_index=np.zeros(len(counts), np.int32),
        cyclic=np.zeros(len(counts), bool),  # closed splines already repeat their start
        selected=np.ones(len(counts), bool), curve_type=np.full(len(counts), 1, np.int8))


def to_sketch(data: DrawingData, strokes: list[int], plane: Plane) -> Sketch:
    """The chosen strokes of a drawing as a 2D core sketch; ``source_id`` is the index."""
    slices = data.stroke_slices()
    out = []
    for k in strokes:
        pts = data.positions[slices[k]]
        if data.cyclic[k] and len(pts) > 2:
            pts = np.concatenate([pts, pts[:1]])
            radius = np.concatenate([data.radius[slices[k]], data.radius[slices[k]][:1]])
        else:
            radius = data.radius[slices[k]]
        out.append(Stroke(plane.to_2d(pts), width=radius, source_id=k,
                          style=str(int(data.material_index[k]))))
    if not out:
        raise SketchError("no strokes to simplify")
    return Sketch(out)


def _handles(bezier: np.ndarray, closed: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    knots, right, left = bezier[::3], bezier[1::3], bezier[2::3]
    if closed:  # the last knot repeats the first: drop it, wrap the handles round
        knots = knots[:-1]
        return knots, np.concatenate([left[-1:], left[:-1]]), right
    return (knots, np.concatenate([2 * knots[:1] - right[:1], left]),
            np.concatenate([right, 2 * knots[-1:] - left[-1:]]))


#: each fitted cubic is written as this many (the same shape, subdivided exactly), so that
#: radius, opacity and colour, given per knot, follow the ink along the stroke: with one
#: knot per cubic an output stroke had about 4 radii, and its tapered ends were lost
KNOTS_PER_SEGMENT = 3


def _dominant_colour(colours: np.ndarray) -> np.ndarray:
    """Which points carry the colour most of the ink has (colours compared to 1/256), so
    that differently coloured strokes in one bundle are never mixed."""
    keys = np.round(colours * 255).astype(np.int32)
    _, label, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    return label.ravel() == np.argmax(counts)


def _nearest(points: np.ndarray, ink: np.ndarray) -> np.ndarray:
    """Index into ``ink`` of the nearest ink point of each point (a tree: a long stroke
    of a dense drawing has tens of thousands of source points)."""
    i, k = shapely.STRtree(shapely.points(ink)).query_nearest(shapely.points(points),
                                                              all_matches=False)
    out = np.empty(len(points), np.intp)
    out[i] = k
    return out


def to_new_strokes(result_strokes: list[Stroke], data: DrawingData, plane: Plane,
                   reach: float = 0.0) -> NewStrokes:
    """Output strokes as Bezier knots and handles on the plane, with attributes per knot:
    the radius the core carried over from the ink (its profile, ends tapered as drawn),
    opacity from the nearest ink point of the stroke's sources, and vertex colour from the
    nearest of those that have the stroke's main colour, where such ink lies within
    ``reach`` (the bundle width) of the knot; elsewhere from the nearest ink of any colour.
    A bundle of red and blue passes stays one colour; a circle drawn half red, half blue
    comes out half red, half blue."""
    slices = data.stroke_slices()
    ink = plane.to_2d(data.positions)
    step = SAMPLES_PER_SEGMENT // KNOTS_PER_SEGMENT
    knots, lefts, rights, radii, opacity, colours, materials, cyclic = ([] for _ in range(8))
    for s in result_strokes:
        k, hl, hr = _handles(subdivide_bezier(s.bezier, KNOTS_PER_SEGMENT), s.closed)
        knots.append(plane.to_3d(k))
        lefts.append(plane.to_3d(hl))
        rights.append(plane.to_3d(hr))
        at_knots = np.minimum(np.arange(len(k)) * step, len(s.points) - 1)
        width = s.width if s.width is not None else np.full(len(s.points), 0.01)
        # a radius below 0 or an opacity outside 0..1 in the ink (a broken import, a script)
        # is not copied on: Blender draws such strokes wrongly or not at all
        radii.append(np.maximum(width[at_knots], 0.0).astype(np.float32))
        src = list(s.sources) or [0]
        src_points = np.concatenate([np.arange(slices[i].start, slices[i].stop) for i in src])
        src_points = src_points[np.isfinite(ink[src_points]).all(axis=1)]
        near = src_points[_nearest(k, ink[src_points])]
        opacity.append(np.clip(data.opacity[near], 0.0, 1.0).astype(np.float32))
        if data.vertex_color is not None:
            main = src_points[_dominant_colour(data.vertex_color[src_points])]
            on_main = main[_nearest(k, ink[main])]
            away = np.hypot(*(ink[on_main] - k).T) > reach  # no ink of the main colour here
            colours.append(data.vertex_color[np.where(away, near, on_main)].astype(np.float32))
        material = Counter(int(data.material_index[i]) for i in src).most_common(1)[0][0]
        materials.append(int(s.style) if s.style is not None else material)
        cyclic.append(bool(s.closed))
    return NewStrokes(knots, lefts, rights, radii, opacity,
                      colours if data.vertex_color is not None else None,
                      np.array(materials, np.int32), np.array(cyclic, bool))


#: the radius of fill strokes: their outline is not meant to show
FILL_RADIUS = 0.001


def fill_strokes(regions: list[Region], plane: Plane, fill: int, hole: int) -> NewStrokes:
    """Closed regions as cyclic strokes on the drawing's plane: each outline with material
    ``fill``, then its holes with material ``hole`` (a holdout: it cuts the fill drawn
    before it). Straight between the region's points: the handles sit on the knots."""
    rings, materials = [], []
    for region in regions:
        rings.append(region.outline)
        materials.append(fill)
        rings += list(region.holes)
        materials += [hole] * len(region.holes)
    knots = [plane.to_3d(ring) for ring in rings]
    return NewStrokes(knots, knots, knots,
                      [np.full(len(k), FILL_RADIUS, np.float32) for k in knots],
                      [np.ones(len(k), np.float32) for k in knots], None,
                      np.array(materials, np.int32), np.ones(len(knots), bool))


def stroke_moved(stroke: Stroke, before: Plane, after: Plane) -> Stroke:
    """An output stroke of a drawing on plane ``before``, in the 2D frame of ``after``
    (another keyframe's drawing of the same layer)."""
    return replace(stroke, points=after.moved_from(before, stroke.points),
                   bezier=None if stroke.bezier is None else after.moved_from(before,
                                                                              stroke.bezier))
