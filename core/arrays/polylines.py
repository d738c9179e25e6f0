"""Polylines as numpy arrays: arc lengths, sampling and resampling, of one polyline or of
many at once, their points in one array, each run of them one polyline.

The merge loop works on hundreds of small polylines at a time, where numpy's per-call cost
outweighs the arithmetic; held in one array, most steps are a few calls for all of them.

Every result here is bitwise what the same function gives for each polyline alone, however
the polylines are grouped: the merge loop groups them by what it happens to have pending,
and ``result.at(epsilon)`` must equal a fresh run exactly. So arc lengths are summed within
each polyline (never carried over from the one before), and a polyline is sampled as
``np.interp`` samples it alone: on its own slice, or, where each polyline has few samples,
with the segments found on one axis where the polylines lie end to end, then checked on
their own arc lengths (shifted, they round differently) and interpolated by the same
arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

__all__ = [
    "arc_lengths", "end_to_end", "ends_meet", "gaussian_kernel", "leading_count", "points_at",
    "Polylines", "resample_each", "resample_polyline", "resample_polylines", "smoothed_ring",
    "split", "starts", "total_lengths", "true_runs",
]


def gaussian_kernel(sigma: float, half: int) -> np.ndarray:
    """Weights summing to 1 of a Gaussian of ``sigma`` samples, at offsets -half..half:
    what smoothing along an evenly spaced polyline convolves with.

    >>> gaussian_kernel(1.0, 1).round(3).tolist()
    [0.274, 0.452, 0.274]
    """
    k = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma) ** 2)
    return k / k.sum()


def smoothed_ring(values: np.ndarray, sigma: float) -> np.ndarray:
    """Values along an evenly spaced ring, (n,) or (n, d), its first repeated last,
    smoothed by a Gaussian of ``sigma`` samples (:func:`gaussian_kernel`, 3 sigma each
    side) wrapping round its seam; the first is repeated last again.

    >>> bump = np.array([3.0, 0, 0, 0, 0, 0, 0, 0, 3])  # at the seam: spreads both ways
    >>> smoothed_ring(bump, 1.0).round(2).tolist()
    [1.2, 0.73, 0.16, 0.01, 0.0, 0.01, 0.16, 0.73, 1.2]
    """
    half = int(np.ceil(3 * sigma))
    k = gaussian_kernel(sigma, half)
    ring = values[:-1]
    pad = np.pad(ring, [(half, half)] + [(0, 0)] * (ring.ndim - 1), mode="wrap")
    if pad.ndim == 1:
        out = np.convolve(pad, k, mode="valid")
    else:
        out = np.column_stack([np.convolve(pad[:, d], k, mode="valid")
                               for d in range(pad.shape[1])])
    return np.concatenate([out, out[:1]])


def leading_count(mask: np.ndarray) -> int | np.ndarray:
    """How many of a polyline's points, from its first, pass a test: the number of True
    values ``mask`` starts with along its first axis (for each column of a 2-D mask).

    >>> leading_count(np.array([True, True, False, True]))
    2
    >>> leading_count(np.array([[True, False], [True, True]])).tolist()
    [2, 0]
    """
    count = np.where(mask.all(axis=0), len(mask), np.argmin(mask, axis=0))
    return int(count) if mask.ndim == 1 else count


def true_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of each run of True.

    >>> true_runs(np.array([True, False, True, True]))
    [(0, 0), (2, 3)]
    """
    edges = np.diff(np.r_[0, mask.astype(np.int8), 0])
    firsts, lasts = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return list(zip(firsts.tolist(), lasts.tolist()))


def starts(sizes: np.ndarray) -> np.ndarray:
    """Where each of consecutive runs of these sizes starts."""
    first = np.zeros(len(sizes), dtype=np.intp)
    if len(sizes) > 1:
        np.cumsum(sizes[:-1], out=first[1:])
    return first


def end_to_end(polylines: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The points of all polylines in one array, and the index of each one's first point
    and of its last."""
    sizes = np.fromiter(map(len, polylines), dtype=np.intp, count=len(polylines))
    first = starts(sizes)
    points = polylines[0] if len(polylines) == 1 else np.concatenate(polylines)
    return points, first, first + sizes - 1


def split(x: np.ndarray, sizes: np.ndarray) -> list[np.ndarray]:
    """``x`` cut into consecutive runs of these sizes (np.split is slow for many)."""
    if len(sizes) == 1:
        return [x]
    ends = np.cumsum(sizes).tolist()
    return [x[a:b] for a, b in zip([0] + ends[:-1], ends)]


def arc_lengths(points: np.ndarray, first: np.ndarray | None = None,
                last: np.ndarray | None = None) -> np.ndarray:
    """Cumulative arc length at each point, from 0 at the first point: of one polyline, or
    along each of many laid end to end (points ``first[k]`` to ``last[k]``), each one to
    the bit what it gives alone.

    >>> arc_lengths(np.array([[0., 0], [3, 4], [3, 5]])).tolist()
    [0.0, 5.0, 6.0]
    """
    d = points[1:] - points[:-1]
    step = np.empty(len(points))
    step[0] = 0.0
    np.hypot(d[:, 0], d[:, 1], out=step[1:])
    if first is None or len(first) == 1:
        return np.cumsum(step)
    sizes = last - first + 1
    if len(sizes) * int(sizes.max()) <= 4 * len(points):
        return _running_sums(step, first, sizes)[0]
    # rows of very different lengths: padded in groups within a factor of two of each other
    out = np.empty(len(points))
    group = np.frexp(sizes)[1]
    for g in np.unique(group).tolist():
        ks = np.flatnonzero(group == g)
        values, at = _running_sums(step, first[ks], sizes[ks])
        out[at] = values
    return out


def _running_sums(step: np.ndarray, first: np.ndarray, sizes: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The running sum of ``step`` along each polyline (from 0 at its first point), and
    the indices of its points: one row per polyline, padded with zeros, so that the sum
    along a row adds the same numbers in the same order as for the polyline alone."""
    which = np.repeat(np.arange(len(sizes)), sizes)
    col = np.arange(len(which)) - starts(sizes)[which]
    at = first[which] + col
    rows = np.zeros((len(sizes), int(sizes.max())))
    rows[which, col] = step[at]
    rows[:, 0] = 0.0
    return np.cumsum(rows, axis=1)[which, col], at


def ends_meet(points: np.ndarray, reach: float, share: float) -> bool:
    """Whether a polyline comes round to where it began: its ends lie within ``reach`` of
    each other and within ``share`` of its length (a small ring drawn whole does; a U,
    whose ends lie a third of its length apart, does not).

    >>> t = np.linspace(0, 2 * np.pi, 40)
    >>> ring = np.stack([np.cos(t), np.sin(t)], axis=1)
    >>> ends_meet(ring, 0.5, 0.25), ends_meet(ring[:-8], 0.5, 0.25), ends_meet(ring[:24], 9, 0.25)
    (True, False, False)
    """
    if len(points) < 3:
        return False
    gap = float(np.hypot(*(points[0] - points[-1])))
    return gap <= reach and gap < share * float(arc_lengths(points)[-1])


def total_lengths(polylines: list[np.ndarray]) -> np.ndarray:
    """The length of each polyline: ``arc_lengths(p)[-1]`` of each, to the bit."""
    if not polylines:
        return np.empty(0)
    points, first, last = end_to_end(polylines)
    return arc_lengths(points, first, last)[last]


@dataclass(eq=False)
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
        flat, first, last = end_to_end(points)
        return cls.of_flat(np.concatenate(arcs), flat, first, last)

    @classmethod
    def of_flat(cls, s: np.ndarray, points: np.ndarray, first: np.ndarray, last: np.ndarray
                ) -> Polylines:
        """From the arc lengths and points of all, and where each polyline starts and ends."""
        return cls(s, np.ascontiguousarray(points[:, 0]), np.ascontiguousarray(points[:, 1]),
                   first, last)

    @cached_property
    def _axis(self) -> tuple[np.ndarray, np.ndarray]:
        """The arc lengths shifted onto one axis where each polyline lies one unit past the
        one before (increasing over all), and each polyline's shift."""
        lo, hi = self.s[self.first], self.s[self.last]
        shift = np.zeros(len(lo))
        np.cumsum((hi - lo + 1.0)[:-1], out=shift[1:])
        shift -= lo
        return self.s + np.repeat(shift, self.last - self.first + 1), shift

    def _search(self, which: np.ndarray, t: np.ndarray, side: str) -> np.ndarray:
        """np.searchsorted of each t[i] in the arc lengths of polyline which[i], as an
        index into all (clipped to that polyline): searched on the shifted axis, then made
        exact on its own arc lengths (the shift may round t across a vertex)."""
        axis, shift = self._axis
        s, first, last = self.s, self.first[which], self.last[which]
        j = np.searchsorted(axis, t + shift[which], side=side)
        j = np.minimum(np.maximum(j, first), last + 1)
        while True:  # j: the first point past t ("right") or at or past it ("left")
            before = s[np.maximum(j - 1, first)]
            at_j = s[np.minimum(j, last)]
            past = (before > t) if side == "right" else (before >= t)
            short = (at_j <= t) if side == "right" else (at_j < t)
            back = (j > first) & past
            on = (j <= last) & short
            if not (back.any() or on.any()):
                return j
            j = j - back + on

    def at(self, which: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Polyline ``which[i]`` (grouped by polyline) at its arc length ``t[i]``, held at
        its ends: ``np.interp`` on that polyline alone, to the bit."""
        out = np.empty((len(t), 2))
        s, x, y = self.s, self.x, self.y
        if len(self.first) == 1 or len(t) > 64 * len(self.first):  # np.interp on each
            bounds = np.searchsorted(which, np.arange(len(self.first) + 1)).tolist()
            for a, b, lo, hi in zip(bounds[:-1], bounds[1:], self.first.tolist(),
                                    (self.last + 1).tolist()):
                if a < b:
                    out[a:b, 0] = np.interp(t[a:b], s[lo:hi], x[lo:hi])
                    out[a:b, 1] = np.interp(t[a:b], s[lo:hi], y[lo:hi])
            return out
        # few points on each: all segments found at once, and np.interp's arithmetic
        first, last = self.first[which], self.last[which]
        t = np.minimum(np.maximum(t, s[first]), s[last])
        j = self._search(which, t, "right") - 1
        nxt = np.minimum(j + 1, last)
        held = (j == last) | (s[j] == t)  # np.interp gives the point itself there
        ds = s[nxt] - s[j]
        ds[held] = 1.0
        for k, c in enumerate((x, y)):
            out[:, k] = np.where(held, c[j], (c[nxt] - c[j]) / ds * (t - s[j]) + c[j])
        return out

    def index(self, which: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Index (into the points of all) of the first point of polyline ``which[i]``
        (grouped by polyline) at or past arc length ``t[i]``, its last point if none is."""
        return np.minimum(self._search(which, t, "left"), self.last[which])


def resample_polyline(points: np.ndarray, spacing: float) -> np.ndarray:
    """Points evenly spaced by arc length (at most ``spacing`` apart), ends kept; a closed
    polyline keeps at least four, so that it stays a loop however short."""
    s = arc_lengths(points)
    closed = len(points) > 2 and points[0, 0] == points[-1, 0] and points[0, 1] == points[-1, 1]
    n = max(4 if closed else 2, int(np.ceil(s[-1] / spacing)) + 1)
    t = np.arange(n) * (s[-1] / (n - 1))
    t[-1] = s[-1]
    return points_at(t, s, points)


def points_at(t: np.ndarray, s: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The polyline ``points``, whose arc length at each point is ``s``, at arc lengths
    ``t`` (linear between its points)."""
    out = np.empty((len(t), 2))
    out[:, 0] = np.interp(t, s, points[:, 0])
    out[:, 1] = np.interp(t, s, points[:, 1])
    return out


def resample_each(polylines: list[np.ndarray], spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """Each of a list of polylines (each at least one point) resampled every ``spacing``
    (:func:`resample_polylines`): the points of all and how many each has.

    >>> points, sizes = resample_each([np.array([[0.0, 0.0], [1.0, 0.0]]),
    ...                                np.array([[0.0, 1.0], [0.0, 3.0]])], 0.5)
    >>> sizes.tolist(), points[sizes[0]].tolist()
    ([3, 5], [0.0, 1.0])
    """
    sizes = np.fromiter(map(len, polylines), dtype=np.intp, count=len(polylines))
    if not polylines:
        return np.empty((0, 2)), sizes
    return resample_polylines(np.concatenate(polylines), sizes, spacing)


def resample_polylines(points: np.ndarray, sizes: np.ndarray, spacing: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Consecutive polylines (runs of ``sizes`` points) each resampled as by
    :func:`resample_polyline`, to the bit; the points of all and the new sizes."""
    first = starts(sizes)
    last = first + sizes - 1
    s = arc_lengths(points, first, last)
    length = s[last]
    closed = (sizes > 2) & (points[first] == points[last]).all(axis=1)
    n = np.maximum(np.where(closed, 4, 2), np.ceil(length / spacing).astype(np.intp) + 1)
    lines = Polylines.of_flat(s, points, first, last)
    which = np.repeat(np.arange(len(n)), n)
    start = starts(n)
    t = (np.arange(len(which)) - start[which]) * (length / (n - 1))[which]
    t[start + n - 1] = length
    return lines.at(which, t), n
