"""Carrying width, pressure and style from the input strokes over to output strokes.

Each output point takes the width and pressure found, by arc length, at the nearest point
of the nearest input stroke; a stroke's style is the most common style among the input
strokes nearest to its points. All look-ups for a stroke are a few vectorised calls: the
per-point values of every input stroke sit in one array, indexed by a running arc length.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np
import shapely

from ..arrays.geometry import Segments
from ..arrays.polylines import arc_lengths
from ..sketch import Stroke
from .memo import LruStore

__all__ = ["Carried", "InkRows", "NearestInk"]


@dataclass(frozen=True)
class Carried:
    """What an output polyline takes from the nearest ink."""

    width: np.ndarray | None  #: per point
    pressure: np.ndarray | None  #: per point
    style: str | None  #: the most common style of the nearest input strokes
    sources: tuple[int, ...]  #: ids of the input strokes nearest to its points

    def copy(self) -> Carried:
        """With its own per-point arrays (a kept one is not handed out to be changed)."""
        return Carried(None if self.width is None else self.width.copy(),
                       None if self.pressure is None else self.pressure.copy(),
                       self.style, self.sources)


@dataclass(frozen=True)
class InkRows:
    """The input strokes passing near each of some points (:meth:`NearestInk.passing`),
    grouped by point: the rows of point k are ``first[k]:first[k + 1]``, one for each
    segment of a stroke within the radius asked."""

    first: np.ndarray  #: (n + 1,) where each point's rows start (and where the last ends)
    stroke: np.ndarray  #: input stroke of each row (its index among the strokes given)
    at: np.ndarray  #: where along it it passes the point: the running arc length

    def of(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """The strokes passing near point k, and where along each."""
        rows = slice(self.first[k], self.first[k + 1])
        return self.stroke[rows], self.at[rows]


class NearestInk:
    """Nearest-stroke look-ups over the input strokes (given in the unit frame)."""

    def __init__(self, strokes: list[Stroke], unit_points: list[np.ndarray],
                 radius: float = 0.02) -> None:
        self.strokes = strokes
        self.unit_points = unit_points  #: the strokes' points in the unit frame
        self.radius = radius
        s = [arc_lengths(p) for p in unit_points]
        # one increasing "running arc length" over all strokes, a gap of 1 between them
        offset = np.concatenate([[0.0], np.cumsum([x[-1] + 1.0 for x in s])[:-1]])
        self.running = np.concatenate([x + o for x, o in zip(s, offset)])
        self.segments = Segments.of(unit_points)
        self.values = {name: self._stack(name) for name in ("width", "pressure")}
        # what each output polyline took, by content: a slider's replays share most strokes
        # (bounded, and a value depends on its key alone: see core.curves.memo)
        self._taken: LruStore[bytes, Carried] = LruStore()

    def _stack(self, name: str) -> np.ndarray | None:
        arrays = [getattr(st, name) for st in self.strokes]
        if all(a is None for a in arrays):
            return None
        return np.concatenate([a if a is not None else np.full(len(st.points), np.nan)
                               for a, st in zip(arrays, self.strokes)])

    def passing(self, points: np.ndarray, radius: float) -> InkRows:
        """The input strokes passing within ``radius`` of each of ``points`` (n, 2), and
        where along each they come nearest (a stroke passing near twice: twice).

        >>> line = np.array([[0.0, 0.0], [1.0, 0.0]])
        >>> rows = NearestInk([Stroke(line)], [line]).passing(np.array([[0.5, 0.05],
        ...                                                              [0.5, 1.0]]), 0.1)
        >>> [(s.tolist(), at.round(2).tolist()) for s, at in (rows.of(0), rows.of(1))]
        [([0], [0.5]), ([], [])]
        """
        geoms = shapely.points(points)
        segs = self.segments
        i, seg = segs.tree.query(geoms, predicate="dwithin", distance=radius)
        order = np.argsort(i, kind="stable")
        i, seg = i[order], seg[order]
        at = self.running[segs.start[seg]] + segs.along(seg, points[i])
        return InkRows(np.searchsorted(i, np.arange(len(points) + 1)), segs.polyline[seg], at)

    def _nearest(self, geoms: np.ndarray) -> np.ndarray:
        """Index of the nearest input segment of each point. A search bounded to a small
        radius is much quicker; the few points it leaves unmatched are searched fully."""
        nearest = np.full(len(geoms), -1)
        tree = self.segments.tree
        i, k = tree.query_nearest(geoms, max_distance=self.radius, all_matches=False)
        nearest[i] = k
        rest = np.flatnonzero(nearest < 0)
        if len(rest):
            i, k = tree.query_nearest(geoms[rest], all_matches=False)
            nearest[rest[i]] = k
        return nearest

    def transfer(self, strokes: list[np.ndarray]) -> list[Carried]:
        """For each polyline: width and pressure per point, style, ids of the input strokes.

        One nearest-neighbour query serves all polylines not seen before at once.
        """
        keys = [p.tobytes() for p in strokes]
        found = {key: self._taken.get(key) for key in keys if key in self._taken}
        todo = list({key: p for key, p in zip(keys, strokes) if key not in found}.items())
        for (key, _), carried in zip(todo, self._transfer([p for _, p in todo])):
            found[key] = carried
            self._taken.put(key, carried)
        return [found[key].copy() for key in keys]

    def _transfer(self, strokes: list[np.ndarray]) -> list[Carried]:
        if not strokes:
            return []
        counts = [len(p) for p in strokes]
        points = np.concatenate(strokes)
        segment = self._nearest(shapely.points(points))
        segs = self.segments
        nearest = segs.polyline[segment]
        where = self.running[segs.start[segment]] + segs.along(segment, points)
        cuts = np.cumsum(counts)[:-1]
        split = {name: [None] * len(strokes) if v is None else
                 np.split(np.interp(where, self.running, v), cuts)
                 for name, v in self.values.items()}
        out = []
        for k, near in enumerate(np.split(nearest, cuts)):
            per_point = []
            for name in ("width", "pressure"):
                v = split[name][k]
                per_point.append(None if v is None or np.isnan(v).all() else
                                 np.where(np.isnan(v), np.nanmean(v), v))
            used = np.unique(near).tolist()
            ids = tuple(sorted({self.strokes[i].source_id if self.strokes[i].source_id
                                is not None else i for i in used}))
            styles = Counter(self.strokes[i].style for i in near.tolist()
                             if self.strokes[i].style is not None)
            out.append(Carried(per_point[0], per_point[1],
                               styles.most_common(1)[0][0] if styles else None, ids))
        return out
