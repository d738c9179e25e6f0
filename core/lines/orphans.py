"""Pass 8 of :mod:`core.lines`: ink no line stands for. A loose pass that parts from its
line by more than a loose pass lies off the middle (``tuning.member_reach`` d_eps) is
still a member where it runs along the line for most of its length, and the line's median
follows the other passes there: that stretch of ink is stood for by no line. Each stretch
of a piece at least ``tuning.crumb`` d_eps long (shorter is a hook or a crumb) lying
farther than ``member_reach`` d_eps from every line becomes a line of its own, from where
it leaves the lines (within ``tuning.snap`` d_eps of one, so that pass 9 meets its ends
onto that line) to where it comes back; stretches of several passes lying together are
one line, fitted as pass 4 fits a group; and one that carries on from a free end of a
line (within ``snap``, heading on its way) is drawn on from it, as the pen would. Not at
epsilon 0 (each stroke is its own line).

Invariant, after this pass: every stretch of input ink longer than ``crumb`` d_eps lies within
``member_reach`` d_eps of a line.
"""

from __future__ import annotations

import numpy as np

from ..arrays.geometry import Segments
from ..arrays.polylines import arc_lengths, true_runs
from .chains import End, chain
from .fit import components, fitted_centreline
from .work import Line, Work

__all__ = ["run", "stretches_apart"]


def stretches_apart(distance: np.ndarray, s: np.ndarray, far: float, near: float,
                    length: float) -> list[tuple[int, int]]:
    """The stretches (first, last sample) of a polyline, its samples lying ``distance``
    from the lines at arc lengths ``s``, that lie farther than ``far`` along at least
    ``length``, each widened to the nearest samples within ``near`` either side (or the
    polyline's ends); overlapping ones are one.

    >>> d = np.array([0.0, 0.5, 2.0, 3.0, 3.0, 2.0, 0.5, 0.0, 2.0])
    >>> stretches_apart(d, np.arange(9.0), 1.5, 1.0, 2.0)
    [(1, 6)]
    """
    out: list[tuple[int, int]] = []
    close = np.flatnonzero(distance <= near)
    for a, b in true_runs(distance > far):
        if s[b] - s[a] < length:
            continue
        before, after = close[close < a], close[close > b]
        a = int(before[-1]) if len(before) else 0
        b = int(after[0]) if len(after) else len(distance) - 1
        if out and a <= out[-1][1]:
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def _together(stretches: list[np.ndarray], reach: float, share: float) -> list[list[int]]:
    """``stretches`` in groups: two are one line where ``share`` of the shorter lies within
    ``reach`` of the other (loose passes that parted from the line together)."""
    pairs = []
    for i in range(len(stretches)):
        for j in range(i + 1, len(stretches)):
            short, other = sorted((i, j), key=lambda k: (len(stretches[k]), k))
            near = Segments.of([stretches[other]]).distance(stretches[short]) <= reach
            if near.mean() >= share:
                pairs.append((i, j))
    return components(list(range(len(stretches))),
                      np.array(pairs, dtype=np.intp).reshape(-1, 2))


def run(work: Work) -> Work:
    lines = work.current_lines()
    if not work.merged or not lines or not work.pieces:
        return work.with_(lines=lines)
    t = work.tuning
    sizes = work.piece_sizes()
    segs = Segments.of([ln.points for ln in lines])
    if not len(segs.origin):  # lines of one point each: nothing to measure against
        return work.with_(lines=lines)
    distance = segs.distance(np.concatenate(work.pieces))
    firsts = np.cumsum(sizes) - sizes
    reach = t.member_reach * work.d
    stretches, owner = [], []
    for k in np.flatnonzero(np.maximum.reduceat(distance, firsts) > reach).tolist():
        piece = work.pieces[k]
        for a, b in stretches_apart(distance[firsts[k]:firsts[k] + sizes[k]],
                                    arc_lengths(piece), reach, t.snap * work.d,
                                    t.crumb * work.d):
            stretches.append(piece[a:b + 1])
            owner.append(k)
    extra = []
    for group in _together(stretches, reach, t.together_share):
        line, closed = fitted_centreline([stretches[k] for k in group], work)
        extra.append(Line(line, closed, tuple(sorted({owner[k] for k in group}))))
    if not extra:
        return work.with_(lines=lines)
    everything = lines + extra
    snap = t.snap * work.meet_d
    joins = _drawn_on(everything, range(len(lines), len(everything)), snap, t.follow_cos)
    return work.with_(lines=chain(everything, joins, snap, work.h) if joins else everything)


def _heading(points: np.ndarray, end: int, reach: float) -> np.ndarray:
    """The unit direction a line heads out of its end ``end`` (0 first, 1 last), over its
    last ``reach`` of length."""
    pts = points if end == 1 else points[::-1]
    s = arc_lengths(pts)
    back = pts[int(np.searchsorted(s, s[-1] - reach))] if s[-1] > reach else pts[0]
    v = pts[-1] - back
    return v / max(float(np.hypot(*v)), 1e-300)


def _drawn_on(lines: list[Line], new, reach: float, along_cos: float
              ) -> list[tuple[End, End]]:
    """Ends of the ``new`` lines that carry on from a free end of another line: within
    ``reach`` of it, heading on the way it heads (cos at least ``along_cos``), the
    nearest first, each end once."""
    found = []
    ends = np.array([[ln.points[0], ln.points[-1]] for ln in lines])  # (lines, 2, 2)
    free = ~np.array([ln.closed for ln in lines])
    for o in new:
        for e in (0, 1):
            gaps = np.hypot(*(ends - ends[o, e]).transpose(2, 0, 1))  # (lines, 2)
            gaps[o] = np.inf
            for k, f in zip(*np.nonzero((gaps <= reach) & free[:, None])):
                heads = _heading(lines[k].points, int(f), reach) @ -_heading(
                    lines[o].points, e, reach)
                if heads >= along_cos:
                    found.append((float(gaps[k, f]), (o, e), (int(k), int(f))))
    used: set[End] = set()
    joins = []
    for _, x, y in sorted(found):
        if x not in used and y not in used and x[0] != y[0]:
            used.update((x, y))
            joins.append((min(x, y), max(x, y)))
    return joins
