"""Many polylines at once: their points in one array, each run of them one polyline.

The merge loop works on hundreds of small polylines at a time, where numpy's per-call cost
outweighs the arithmetic; held in one array, most steps are a few calls for all of them.

Every result here is bitwise what the same function gives for each polyline alone, however
the polylines are grouped: the merge loop groups them by what it happens to have pending,
and ``result.at(epsilon)`` must equal a fresh run exactly. So arc lengths are summed within
each polyline (never carried over from the one before), and sampling is ``np.interp`` on
each polyline's own slice (laid end to end on one shifted axis, rounding would depend on
the polylines before).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def starts(sizes: np.ndarray) -> np.ndarray:
    """Where each of consecutive runs of these sizes starts."""
    first = np.zeros(len(sizes), dtype=np.intp)
    if len(sizes) > 1:
        np.cumsum(sizes[:-1], out=first[1:])
    return first


def split(x: np.ndarray, sizes: np.ndarray) -> list[np.ndarray]:
    """``x`` cut into consecutive runs of these sizes (np.split is slow for many)."""
    if len(sizes) == 1:
        return [x]
    ends = np.cumsum(sizes).tolist()
    return [x[a:b] for a, b in zip([0] + ends[:-1], ends)]


def arc_lengths(points: np.ndarray, first: np.ndarray, last: np.ndarray) -> np.ndarray:
    """Arc length along each polyline (points ``first[k]`` to ``last[k]``), from 0 at its
    first point: :func:`core.geometry.arc_lengths` of each, to the bit."""
    d = points[1:] - points[:-1]
    step = np.empty(len(points))
    step[0] = 0.0
    np.hypot(d[:, 0], d[:, 1], out=step[1:])
    sizes = last - first + 1
    if len(sizes) == 1:
        step[0] = 0.0
        return np.cumsum(step)
    if len(sizes) * int(sizes.max()) > 4 * len(points):  # rows mostly padding: one by one
        return np.concatenate([np.cumsum(np.append(0.0, step[a + 1:b + 1]))
                               for a, b in zip(first.tolist(), last.tolist())])
    # one row per polyline, padded with zeros: a running sum along each row adds the same
    # numbers in the same order as for the polyline alone
    which = np.repeat(np.arange(len(sizes)), sizes)
    col = np.arange(len(points)) - first[which]
    rows = np.zeros((len(sizes), int(sizes.max())))
    rows[which, col] = step
    rows[:, 0] = 0.0
    return np.cumsum(rows, axis=1)[which, col]


@dataclass
class Polylines:
    """Polylines with their arc lengths, the points of all in one array."""

    s: np.ndarray  # each polyline's own arc lengths, all
    x: np.ndarray  # the points' coordinates, all
    y: np.ndarray
    first: np.ndarray  # per polyline: the index of its first point and of its last
    last: np.ndarray

    @classmethod
    def of(cls, arcs: list[np.ndarray], points: list[np.ndarray]) -> Polylines:
        """From each polyline's arc lengths and points."""
        sizes = np.fromiter(map(len, arcs), dtype=np.intp, count=len(arcs))
        first = starts(sizes)
        return cls.of_flat(np.concatenate(arcs), np.concatenate(points), first,
                           first + sizes - 1)

    @classmethod
    def of_flat(cls, s: np.ndarray, points: np.ndarray, first: np.ndarray, last: np.ndarray
                ) -> Polylines:
        """From the arc lengths and points of all, and where each polyline starts and ends."""
        return cls(s, np.ascontiguousarray(points[:, 0]), np.ascontiguousarray(points[:, 1]),
                   first, last)

    def _runs(self, which: np.ndarray) -> zip:
        """Per polyline: where its queries (``which`` grouped by polyline) and its points
        start and end."""
        bounds = np.searchsorted(which, np.arange(len(self.first) + 1)).tolist()
        return zip(bounds[:-1], bounds[1:], self.first.tolist(), (self.last + 1).tolist())

    def at(self, which: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Polyline ``which[i]`` (grouped by polyline) at its arc length ``t[i]``, held at
        its ends: ``np.interp`` on that polyline alone."""
        out = np.empty((len(t), 2))
        s, x, y = self.s, self.x, self.y
        for a, b, lo, hi in self._runs(which):
            if a < b:
                out[a:b, 0] = np.interp(t[a:b], s[lo:hi], x[lo:hi])
                out[a:b, 1] = np.interp(t[a:b], s[lo:hi], y[lo:hi])
        return out

    def index(self, which: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Index (into the points of all) of the first point of polyline ``which[i]``
        (grouped by polyline) at or past arc length ``t[i]``, its last point if none is."""
        out = np.empty(len(t), dtype=np.intp)
        for a, b, lo, hi in self._runs(which):
            if a < b:
                out[a:b] = np.minimum(np.searchsorted(self.s[lo:hi], t[a:b]), hi - lo - 1) + lo
        return out
