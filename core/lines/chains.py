"""Lines joined end to end (:mod:`core.lines` passes 7 and 8 share it: corners, and a
stretch of ink drawn on from a free end): each end joined to
at most one other; a chain that comes back to its start is closed."""

from __future__ import annotations

import numpy as np
import shapely

from ..arrays.polylines import resample_polyline
from .junctions import cut_to, tip_of
from .work import Line

__all__ = ["End", "chain", "meeting"]

#: a line end: (line index, 0 for its first point or 1 for its last)
End = tuple[int, int]


def meeting(a: np.ndarray, end_a: int, b: np.ndarray, end_b: int, reach: float
            ) -> np.ndarray:
    """Where two ends meet: where their tips (``reach`` long) cross, else the middle of
    the two end points.

    >>> a = np.array([[0.0, 0.0], [1.1, 0.0]])  # overshoots the corner at (1, 0)
    >>> b = np.array([[1.0, -0.1], [1.0, 1.0]])
    >>> meeting(a, 1, b, 0, 0.5).round(3).tolist()
    [1.0, 0.0]
    """
    x = shapely.intersection(shapely.LineString(tip_of(a, end_a, reach)),
                             shapely.LineString(tip_of(b, end_b, reach)))
    pts = shapely.get_coordinates(x)
    if len(pts):
        e = a[0] if end_a == 0 else a[-1]
        return pts[np.argmin(np.hypot(*(pts - e).T))]
    return 0.5 * ((a[0] if end_a == 0 else a[-1]) + (b[0] if end_b == 0 else b[-1]))


def chain(lines: list[Line], joins: list[tuple[End, End]], reach: float, h: float
          ) -> list[Line]:
    """``lines`` with each pair of ends in ``joins`` joined where they meet
    (:func:`meeting`); every end is in at most one join.

    >>> a = Line(np.array([[0.0, 0.0], [1.0, 0.0]]), False, (0,))
    >>> b = Line(np.array([[1.0, 0.0], [1.0, 1.0]]), False, (1,))
    >>> [(len(x.points), x.closed, x.members) for x in chain([a, b], [((0, 1), (1, 0))],
    ...                                                        0.2, 0.5)]
    [(5, False, (0, 1))]
    """
    partner: dict[End, End] = {}
    for x, y in joins:
        partner[x], partner[y] = y, x
    points = {k: ln.points for k, ln in enumerate(lines)}
    for x, y in joins:  # each end moved to where the two meet
        at = meeting(points[x[0]], x[1], points[y[0]], y[1], reach)
        points[x[0]] = cut_to(points[x[0]], x[1], at, reach)
        points[y[0]] = cut_to(points[y[0]], y[1], at, reach)
    done: set[int] = set()
    out = []
    order = sorted(range(len(lines)), key=lambda k: ((k, 0) in partner) and ((k, 1) in partner))
    for start in order:  # chains from a free end first, then the cycles left
        if start in done:
            continue
        k, entered = start, 0 if (start, 0) not in partner else 1
        if (start, 0) in partner and (start, 1) not in partner:
            entered = 1
        parts, members, closed = [], [], False
        while True:
            done.add(k)
            pts = points[k] if entered == 0 else points[k][::-1]
            parts.append(pts if not parts else pts[1:])
            members += lines[k].members
            leave = (k, 1 - entered)
            if leave not in partner:
                break
            nxt, nxt_end = partner[leave]
            if nxt in done:
                closed = nxt == start
                break
            k, entered = nxt, nxt_end
        pts = np.concatenate(parts)
        if closed:
            pts = np.concatenate([pts, pts[:1]])
        out.append(Line(resample_polyline(pts, h), closed or (len(parts) == 1
                                                              and lines[start].closed),
                        tuple(sorted(members))))
    return out
