"""Small vectorised helpers between lists of polylines and shapely geometry arrays, the
shoelace formula for ring areas, polylines as single segments crossed by sections, and
which samples of polylines come within a reach of other lines."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np
import shapely

from .polylines import arc_lengths, resample_each

__all__ = [
    "Crossings", "Projection", "Reached", "Segments", "lines_from", "nearest_of_each",
    "polygons_from", "project_on", "ring_is_counter_clockwise", "segment_distance",
    "shoelace_terms", "split_coordinates", "tangents", "tangents_each", "unit_rows",
]


def _flat(polylines: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    counts = np.fromiter((len(p) for p in polylines), dtype=np.intp, count=len(polylines))
    coords = np.concatenate(polylines) if polylines else np.empty((0, 2))
    return coords, np.repeat(np.arange(len(polylines)), counts)


def lines_from(polylines: list[np.ndarray]) -> np.ndarray:
    """One LineString per (k >= 2, 2) polyline, in one vectorised call."""
    coords, index = _flat(polylines)
    return shapely.linestrings(coords, indices=index)


def polygons_from(rings: list[np.ndarray]) -> np.ndarray:
    """One Polygon per ring (first point not repeated; shapely closes it)."""
    closed = [np.concatenate([r, r[:1]]) for r in rings]
    coords, index = _flat(closed)
    return shapely.polygons(shapely.linearrings(coords, indices=index))


def shoelace_terms(curves: list[np.ndarray]) -> np.ndarray:
    """Each polyline's term 1/2 sum(x_i y_i+1 - x_i+1 y_i) of the shoelace formula: the
    signed area of a ring is the sum of the terms of the curves walked round it (minus a
    curve's term where it is walked backwards).

    >>> shoelace_terms([np.array([[0., 0], [1, 0], [1, 1]]), np.array([[1., 1], [0, 0]])])
    array([0.5, 0. ])
    """
    counts = np.fromiter((len(c) for c in curves), dtype=np.intp, count=len(curves))
    pts = np.concatenate(curves)
    cross = pts[:-1, 0] * pts[1:, 1] - pts[1:, 0] * pts[:-1, 1]
    owner = np.repeat(np.arange(len(curves)), counts)[:-1]
    same = owner == np.repeat(np.arange(len(curves)), counts)[1:]
    return 0.5 * np.bincount(owner[same], weights=cross[same], minlength=len(curves))


def ring_is_counter_clockwise(points: np.ndarray) -> bool:
    """Whether a closed ring (first point not repeated) has positive signed area.

    >>> ring_is_counter_clockwise(np.array([[0., 0], [1, 0], [0, 1]]))
    True
    """
    x, y = points[:, 0], points[:, 1]
    return bool(x[:-1] @ y[1:] - x[1:] @ y[:-1] + x[-1] * y[0] - x[0] * y[-1] > 0)


def split_coordinates(geoms: np.ndarray) -> list[np.ndarray]:
    """The coordinates of each geometry, as a list of (k, 2) arrays."""
    coords, index = shapely.get_coordinates(geoms, return_index=True)
    cuts = np.flatnonzero(np.diff(index)) + 1
    return np.split(coords, cuts) if len(coords) else []


def unit_rows(vectors: np.ndarray) -> np.ndarray:
    """Each row of an (n, 2) array of vectors scaled to length 1; zero rows stay zero.

    >>> unit_rows(np.array([[3.0, 4.0], [0.0, 0.0]])).tolist()
    [[0.6, 0.8], [0.0, 0.0]]
    """
    norm = np.hypot(vectors[:, 0], vectors[:, 1])
    return vectors / np.where(norm > 0, norm, 1.0)[:, None]


def tangents(points: np.ndarray, closed: bool = False) -> np.ndarray:
    """Unit tangents (n, 2) of an evenly spaced polyline by central differences (one-sided
    at an open line's ends); a ring's wrap round its seam (its first point repeated
    last); a single point's is 0.

    >>> tangents(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])).round(3).tolist()
    [[1.0, 0.0], [0.707, 0.707], [0.0, 1.0]]
    """
    if len(points) < 2:
        return np.zeros_like(points)
    if not closed:
        return unit_rows(np.gradient(points, axis=0))
    ring = np.vstack([points[-2:-1], points, points[1:2]])
    return unit_rows(np.gradient(ring, axis=0)[1:-1])


def nearest_of_each(i: np.ndarray, dist: np.ndarray, tie: np.ndarray) -> np.ndarray:
    """For rows (``i``, ``dist``, ``tie``) of a query, the index of the row of least
    ``dist`` for each distinct ``i``, of equally near ones the least ``tie``, in
    ascending ``i``: the first row of each ``i`` after ``np.lexsort((tie, dist, i))``, in
    a few passes over the rows where they come sorted by ``i`` (as a tree query gives
    them), without sorting them.

    >>> i, dist = np.array([0, 0, 0, 2, 2]), np.array([2.0, 1, 1, 5, 4])
    >>> tie = np.array([7, 9, 8, 1, 3])
    >>> nearest_of_each(i, dist, tie).tolist()
    [2, 4]
    """
    if not len(i):
        return np.zeros(0, dtype=np.intp)
    if np.any(i[1:] < i[:-1]):
        order = np.lexsort((tie, dist, i))
        return order[np.r_[True, i[order][1:] != i[order][:-1]]]
    starts = np.flatnonzero(np.r_[True, i[1:] != i[:-1]])
    group = np.cumsum(np.r_[False, i[1:] != i[:-1]])
    least = np.minimum.reduceat(dist, starts)
    nearest = dist == least[group]
    rows = np.arange(len(i))
    # of the nearest rows of each group, the least tie, then the first such row
    ties = np.where(nearest, tie, np.iinfo(np.int64).max)
    best = np.minimum.reduceat(ties, starts)
    chosen = np.where(nearest & (ties == best[group]), rows, len(i))
    return np.minimum.reduceat(chosen, starts)


def tangents_each(polylines: list[np.ndarray]) -> np.ndarray:
    """The :func:`tangents` of open polylines, end to end: (total points, 2), each one's
    as it alone gives them, to the bit, in a few array operations.

    >>> lines = [np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]), np.array([[5.0, 5.0]]),
    ...          np.array([[0.0, 0.0], [0.0, 2.0]])]
    >>> bool(np.array_equal(tangents_each(lines), np.concatenate([tangents(p) for p in lines])))
    True
    """
    if not polylines:
        return np.zeros((0, 2))
    sizes = np.fromiter(map(len, polylines), dtype=np.intp, count=len(polylines))
    flat = np.concatenate(polylines).astype(float, copy=False)
    out = np.zeros_like(flat)
    if len(flat) > 2:  # np.gradient's central differences inside each polyline
        out[1:-1] = (flat[2:] - flat[:-2]) / 2.0
    last = np.cumsum(sizes) - 1
    first = last - sizes + 1
    two = sizes >= 2  # its one-sided differences at each end; a single point's is 0
    out[first[two]] = flat[first[two] + 1] - flat[first[two]]
    out[last[two]] = flat[last[two]] - flat[last[two] - 1]
    out[first[~two]] = 0.0
    return unit_rows(out)


#: a nearest query of at most this many (point, segment) pairs is answered by measuring
#: every pair in numpy: most of the pen stage's projections are of a few dozen points on a
#: line of a few dozen segments, where building a tree and walking it costs about three
#: times as much (for larger queries the two cost about the same)
BRUTE_PAIRS = 16384


def segment_distance(points: np.ndarray, origin: np.ndarray, end: np.ndarray
                     ) -> np.ndarray:
    """How far each of ``points`` lies from the segment from ``origin`` to ``end`` (arrays
    of points that broadcast together), measured as GEOS measures it
    (``Distance::pointToSegment``: to an end where the foot falls beyond it), so that a
    test against a reach here agrees with a tree's ``dwithin`` to the bit.

    >>> segment_distance(np.array([[0.5, -1.0], [2.0, 1.0], [3.0, 3.0]]),
    ...                  np.array([0.0, 0.0]), np.array([[1.0, 0.0]])).tolist()
    [1.0, 1.4142135623730951, 3.605551275463989]
    """
    ax, ay, bx, by = origin[..., 0], origin[..., 1], end[..., 0], end[..., 1]
    px, py = points[..., 0], points[..., 1]
    vx, vy = bx - ax, by - ay
    squared = vx * vx + vy * vy
    dxa, dya = px - ax, py - ay
    dxb, dyb = px - bx, py - by
    to_a = np.sqrt(dxa * dxa + dya * dya)
    # every branch is computed; where a segment has no length its r and s are NaN and
    # unused (the distance is to its end)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = ((px - ax) * vx + (py - ay) * vy) / squared
        s = ((ay - py) * vx - (ax - px) * vy) / squared
        return np.where((squared == 0) | (r <= 0), to_a,
                        np.where(r >= 1, np.sqrt(dxb * dxb + dyb * dyb),
                                 np.abs(s) * np.sqrt(squared)))


def _nearest_measured(origin: np.ndarray, end: np.ndarray, points: np.ndarray
                      ) -> np.ndarray:
    """The nearest of the segments from ``origin`` to ``end`` (each (m, 2)) to each of
    ``points`` (of equally near ones the lowest numbered), every pair measured
    (:func:`segment_distance`), so that the same segment is found as a tree's nearest
    query finds.

    >>> _nearest_measured(np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([[1.0, 0.0], [1.0, 1.0]]),
    ...                   np.array([[0.5, -1.0], [2.0, 0.5], [1.5, -0.5]])).tolist()
    [0, 1, 0]
    """
    return np.argmin(segment_distance(points[:, None, :], origin[None], end[None]), axis=1)


@dataclass(frozen=True)
class Segments:
    """Polylines as their single segments ``origin + u * vector`` (u in [0, 1]), each
    numbered by its polyline (``polyline``) and its first point in their concatenation
    (``start``), and in an STRtree when one is asked for (:attr:`tree`): nearest queries
    against single segments are far quicker than against whole polylines of hundreds of
    points.

    >>> segs = Segments.of([np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]),
    ...                     np.array([[0.0, 0.3], [2.0, 0.3]])])
    >>> segs.polyline.tolist(), segs.start.tolist()
    ([0, 0, 1], [0, 1, 3])
    """

    origin: np.ndarray  #: (m, 2)
    vector: np.ndarray  #: (m, 2)
    end: np.ndarray  #: (m, 2) the points the segments end at (``origin + vector`` but for
    #: rounding)
    start: np.ndarray  #: (m,) index of the first point in the polylines' concatenation
    polyline: np.ndarray  #: (m,) which polyline

    @cached_property
    def lines(self) -> np.ndarray:
        """(m,) the segments as shapely LineStrings, made when first asked for."""
        return shapely.linestrings(np.stack([self.origin, self.end], axis=1))

    @cached_property
    def tree(self) -> shapely.STRtree:
        """The segments in an STRtree, built when first asked for (a small nearest query
        needs none)."""
        return shapely.STRtree(self.lines)

    @cached_property
    def whole(self) -> tuple[shapely.STRtree, np.ndarray]:
        """The polylines (those of one segment or more) whole, in an STRtree, and the
        polyline number of each: a query that asks only which polylines come within a
        reach costs one pair per polyline near, not one per segment. GEOS measures a point
        against a LineString segment by segment, as against the single segments, so the
        answers agree to the bit.

        >>> segs = Segments.of([np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]),
        ...                     np.array([[5.0, 5.0]]), np.array([[0.0, 1.0], [2.0, 1.0]])])
        >>> tree, number = segs.whole
        >>> i, k = tree.query(shapely.points([[1.0, 0.4]]), predicate="dwithin", distance=0.5)
        >>> number[k].tolist()
        [0]
        """
        if not len(self.polyline):
            return shapely.STRtree(np.zeros(0, dtype=object)), np.zeros(0, dtype=np.intp)
        number, first = np.unique(self.polyline, return_index=True)
        last = np.r_[first[1:], len(self.polyline)] - 1
        # each polyline's segments' origins, then its last segment's end
        coords = np.insert(self.origin, last + 1, self.end[last], axis=0)
        which = np.insert(self.polyline, last + 1, number)
        lines = shapely.linestrings(coords, indices=np.searchsorted(number, which))
        return shapely.STRtree(lines), number

    @classmethod
    def of(cls, polylines: list[np.ndarray]) -> Segments:
        sizes = np.fromiter(map(len, polylines), dtype=np.intp, count=len(polylines))
        flat = np.concatenate(polylines)
        begins = np.ones(len(flat), bool)  # each point but a polyline's last begins one
        begins[np.cumsum(sizes)[sizes > 0] - 1] = False
        start = np.flatnonzero(begins)
        return cls(flat[start], flat[start + 1] - flat[start], flat[start + 1], start,
                   np.repeat(np.arange(len(sizes)), np.maximum(sizes - 1, 0)))

    def along(self, segment: np.ndarray, points: np.ndarray) -> np.ndarray:
        """How far along each of the given segments its point of ``points`` comes nearest
        (0 to the segment's length): ``shapely.line_locate_point`` on single segments, in
        numpy. GEOS divides by a squared length that underflows on a segment shorter than
        about 1e-160 (a warning and NaN, or an exception); here such a segment gives 0.

        >>> segs = Segments.of([np.array([[0.0, 0.0], [2.0, 0.0]]),
        ...                     np.array([[0.0, 1.0], [1e-200, 1.0]])])
        >>> segs.along(np.array([0, 0, 1]), np.array([[0.5, 1.0], [3.0, 0.0], [1.0, 1.0]]))
        array([0.5, 2. , 0. ])
        """
        d = self.vector[segment]
        squared = (d * d).sum(axis=1)
        u = np.divide(((points - self.origin[segment]) * d).sum(axis=1), squared,
                      out=np.zeros(len(squared)), where=squared > 0)
        return np.clip(u, 0.0, 1.0) * np.sqrt(squared)

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The nearest segment to each of ``points`` (of equally near ones, the lowest
        numbered: the first along its polyline) and how far along it that point comes
        nearest (:meth:`along`). A large query is one tree query, so that a polyline of
        many points costs its log, where GEOS walks every segment of a LineString for each
        point; a small one (``BRUTE_PAIRS``) measures every pair, as GEOS would.

        >>> segs = Segments.of([np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])])
        >>> seg, u = segs.nearest(np.array([[0.5, -1.0], [2.0, 0.5]]))
        >>> seg.tolist(), u.tolist()
        ([0, 1], [0.5, 0.5])
        """
        if len(points) * len(self.origin) <= BRUTE_PAIRS:
            out = _nearest_measured(self.origin, self.end, points)
            return out, self.along(out, points)
        i, seg = self.tree.query_nearest(shapely.points(points), all_matches=True)
        first = nearest_of_each(i, seg, seg)  # of equally near segments, the lowest
        out = np.zeros(len(points), dtype=np.intp)
        out[i[first]] = seg[first]
        return out, self.along(out, points)

    def foot(self, segment: np.ndarray, along: np.ndarray) -> np.ndarray:
        """The points ``along`` (as :meth:`along` gives) each of the given segments."""
        v = self.vector[segment]
        return self.origin[segment] + v * np.divide(
            along, np.hypot(v[:, 0], v[:, 1]), out=np.zeros(len(along)),
            where=along > 0)[:, None]

    def distance(self, points: np.ndarray) -> np.ndarray:
        """How far each of ``points`` lies from the nearest segment.

        >>> segs = Segments.of([np.array([[0.0, 0.0], [2.0, 0.0]])])
        >>> segs.distance(np.array([[1.0, 1.0], [3.0, 0.0]])).tolist()
        [1.0, 1.0]
        """
        seg, u = self.nearest(points)
        return np.hypot(*(points - self.foot(seg, u)).T)

    def running_along(self, points: np.ndarray, tangent: np.ndarray, reach: float,
                      along_cos: float) -> tuple[np.ndarray, np.ndarray]:
        """The segments within ``reach`` of each of ``points`` that run along its
        ``tangent`` (|cos| at least ``along_cos``, either way; a segment of no length
        never does), as rows (point index, segment index).

        >>> segs = Segments.of([np.array([[0.0, 0.1], [1.0, 0.1]]),
        ...                     np.array([[0.5, -1.0], [0.5, 1.0]])])  # along, and across
        >>> i, seg = segs.running_along(np.array([[0.5, 0.0]]), np.array([[1.0, 0.0]]),
        ...                             0.2, 0.9)
        >>> i.tolist(), seg.tolist()
        ([0], [0])
        """
        i, seg = self.tree.query(shapely.points(points), predicate="dwithin", distance=reach)
        v = self.vector[seg]
        length = np.hypot(v[:, 0], v[:, 1])
        keep = (length > 0) & (np.abs((v * tangent[i]).sum(axis=1)) >= along_cos * length)
        return i[keep], seg[keep]

    def crossings(self, points: np.ndarray, tangent: np.ndarray, reach: float,
                  along_cos: float) -> Crossings:
        """Where the segments running along ``tangent`` (|cos| at least ``along_cos``)
        cross the section through each of ``points`` square to it, ``reach`` each side.

        Args:
            points: (n, 2) the sections' middles.
            tangent: (n, 2) unit directions; the sections run along their normals.
            reach: half the length of each section.
            along_cos: the least |cos| between a segment and ``tangent``.

        Returns:
            One row per crossing: its section, its signed distance from the section's
            middle along the normal ``(-tangent[1], tangent[0])``, and the polyline of the
            segment crossing.

        >>> segs = Segments.of([np.array([[0.0, 0.2], [1.0, 0.2]]),
        ...                     np.array([[0.5, -1.0], [0.5, 1.0]])])  # along, and across
        >>> cross = segs.crossings(np.array([[0.5, 0.0]]), np.array([[1.0, 0.0]]), 0.5, 0.9)
        >>> cross.section.tolist(), cross.offset.round(3).tolist(), cross.polyline.tolist()
        ([0], [0.2], [0])
        """
        normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
        sections = shapely.linestrings(np.stack([points - reach * normal,
                                                 points + reach * normal], axis=1))
        sec, seg = self.tree.query(sections, predicate="intersects")
        d = self.vector[seg]
        length = np.hypot(d[:, 0], d[:, 1])
        along = (np.abs((d * tangent[sec]).sum(axis=1)) >= along_cos * length) & (length > 0)
        sec, seg, d = sec[along], seg[along], d[along]
        # the segment o + u d crosses the section p + s n at s = cross(o - p, d) /
        # cross(n, d): never 0, as the segment has a length and runs along, square to n
        rel, n = self.origin[seg] - points[sec], normal[sec]
        offset = (rel[:, 0] * d[:, 1] - rel[:, 1] * d[:, 0]) / (n[:, 0] * d[:, 1]
                                                                 - n[:, 1] * d[:, 0])
        return Crossings(sec, offset, self.polyline[seg])


class Projection(NamedTuple):
    """Points projected onto one polyline (:func:`project_on`)."""

    at: np.ndarray  #: (n,) the arc length along the polyline where each comes nearest
    distance: np.ndarray  #: (n,) how far each lies from it
    length: float  #: the polyline's length


def project_on(line: np.ndarray, points: np.ndarray) -> Projection:
    """``points`` (n, 2) projected onto the polyline ``line`` (k >= 2, 2): what
    ``shapely.line_locate_point`` and ``shapely.distance`` give, through its segments
    (:meth:`Segments.nearest`: a tree of them for a large query, in time growing as n log k
    rather than n k).

    >>> p = project_on(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]),
    ...                np.array([[1.0, 1.0], [3.0, 1.5], [-1.0, 0.0]]))
    >>> p.at.tolist(), p.distance.tolist(), p.length
    ([1.0, 3.5, 0.0], [1.0, 1.0, 1.0], 4.0)
    """
    segs = Segments.of([line])
    seg, u = segs.nearest(points)
    running = arc_lengths(line)
    return Projection(running[segs.start[seg]] + u,
                      np.hypot(*(points - segs.foot(seg, u)).T), float(running[-1]))


@dataclass(frozen=True)
class Crossings:
    """Where polylines cross sections (:meth:`Segments.crossings`), one row per crossing."""

    section: np.ndarray  #: (k,) which section
    offset: np.ndarray  #: (k,) signed distance from the section's middle along its normal
    polyline: np.ndarray  #: (k,) which polyline crosses it


@dataclass(frozen=True)
class Reached:
    """Polylines sampled evenly, and which of some lines each sample comes within a reach
    of (:meth:`of`): one query for every sample of every polyline.

    >>> x = np.linspace(0, 1, 11)[:, None]
    >>> line = [np.hstack([x, 0 * x])]
    >>> across = np.array([[0.5, 0.0], [0.5, 1.0]])  # 11 samples, one within reach
    >>> r = Reached.of([np.hstack([x, 0.01 + 0 * x]), across], line, 0.05, 0.1)
    >>> r.shares().round(2).tolist()
    [1.0, 0.09]
    """

    polyline: np.ndarray  #: (n,) which polyline each sample is of
    count: np.ndarray  #: (k,) samples of each polyline
    sample: np.ndarray  #: (m,) a sample within the reach ...
    line: np.ndarray  #: (m,) ... of this line (a sample near two lines: twice)

    @classmethod
    def of(cls, polylines: list[np.ndarray], lines: list[np.ndarray] | Segments,
           reach: float, spacing: float) -> Reached:
        """``polylines`` (each at least one point) sampled every ``spacing``, against
        ``lines`` (each at least two points). Given as :class:`Segments`, the lines are
        asked through their single segments' tree (kept with them): the same answers, one
        row per (sample, line), in less time where the samples are many against long lines
        or the same lines are asked about again; as polylines, through a tree of them
        whole, made for this query.

        >>> x = np.linspace(0, 1, 11)[:, None]
        >>> lines = [np.hstack([x, 0 * x]), np.hstack([x, 0.02 + 0 * x])]
        >>> a = Reached.of([np.array([[0.0, 0.01], [1.0, 0.01]])], lines, 0.015, 0.5)
        >>> b = Reached.of([np.array([[0.0, 0.01], [1.0, 0.01]])], Segments.of(lines),
        ...                0.015, 0.5)
        >>> a.sample.tolist(), sorted(a.line.tolist()), b.sample.tolist(), b.line.tolist()
        ([0, 0, 1, 1, 2, 2], [0, 0, 0, 1, 1, 1], [0, 0, 1, 1, 2, 2], [0, 1, 0, 1, 0, 1])
        """
        points, count = resample_each(polylines, spacing)
        polyline = np.repeat(np.arange(len(polylines)), count)
        segments = isinstance(lines, Segments)
        if not (len(lines.origin) if segments else len(lines)) or not len(points):
            return cls(polyline, count, np.empty(0, np.intp), np.empty(0, np.intp))
        if not segments:
            sample, line = shapely.STRtree(lines_from(lines)).query(
                shapely.points(points), predicate="dwithin", distance=reach)
            return cls(polyline, count, sample, line)
        sample, seg = lines.tree.query(shapely.points(points), predicate="dwithin",
                                       distance=reach)
        m = int(lines.polyline[-1]) + 1
        key = np.unique(sample.astype(np.int64) * m + lines.polyline[seg])
        return cls(polyline, count, (key // m).astype(np.intp), (key % m).astype(np.intp))

    def near(self) -> np.ndarray:
        """(n,) whether each sample lies within the reach of a line."""
        near = np.zeros(len(self.polyline), dtype=bool)
        near[self.sample] = True
        return near

    def shares(self) -> np.ndarray:
        """(k,) the share of each polyline's samples within the reach of a line."""
        return np.bincount(self.polyline, self.near(), len(self.count)) / np.maximum(
            self.count, 1)
