"""Pass 1 of :mod:`core.lines`: the pen strokes. Each input stroke is resampled every
``h`` (a quarter of d_eps) and cut where it turns more than ``tuning.cut_angle`` within
``tuning.cut_reach`` d_eps each side: a corner drawn in one motion is two lines, which may
belong to two different groups (but a small round shape, turning on the same way beyond,
is no corner: ``tuning.round_share``); and where it comes back along its own earlier ink (a
ring drawn round several times, a line drawn back over itself), each turn a piece, not
where it only crosses it (a cursive l's loop, one line through its crossing). A
stroke that another stroke lies along whole, as it lies along the other (within
``tuning.twin_reach`` d_eps along ``tuning.twin_share`` of each: a shape drawn round
again, a letter written over), is not cut at its corners: the two are passes of one line,
corners and all, fitted whole (pass 4 keeps the corners), not legs that pass 7 joins
again only where every pass was cut alike.
Invariant: the pieces of a stroke, in order, are the
whole stroke (each cut point ends one piece and starts the next); at epsilon 0 (nothing
merged) each stroke is one piece, so that it comes back whole."""

from __future__ import annotations

import numpy as np

from ..arrays.geometry import Segments, segment_distance
from ..arrays.polylines import arc_lengths, resample_polyline, true_runs
from ..curves.bezier import corner_indices
from ..params import Tuning
from .along import twinned
from .work import Work

__all__ = ["cut_at_corners", "cut_where_it_returns", "run"]


def cut_at_corners(points: np.ndarray, spacing: float, angle: float, reach: float,
                   round_share: float = Tuning.round_share) -> list[np.ndarray]:
    """A polyline resampled every ``spacing`` and cut where it turns more than ``angle``
    degrees within ``reach`` each side, unless it goes on turning that way over the next
    ``reach`` beyond, on each side with ink there, at least ``round_share`` as fast per
    length (:func:`core.curves.bezier.turning_on`: round, not a corner).

    >>> corner = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    >>> [p[[0, -1]].tolist() for p in cut_at_corners(corner, 0.25, 70, 0.3)]
    [[[0.0, 0.0], [1.0, 0.0]], [[1.0, 0.0], [1.0, 1.0]]]
    """
    pts = resample_polyline(points, spacing)
    bounds = [0, *corner_indices(pts, angle, reach, round_share), len(pts) - 1]
    return [pts[a:b + 1] for a, b in zip(bounds[:-1], bounds[1:]) if b > a]


def cut_where_it_returns(points: np.ndarray, reach: float, along_cos: float,
                         back: float = Tuning.back) -> list[np.ndarray]:
    """An evenly spaced polyline cut where it comes back within ``reach`` of its own
    earlier ink (farther back along it than ``back`` times that), running along it (|cos| at
    least ``along_cos``, either way): a ring drawn round several times, a line drawn back
    over itself. Each turn is a piece, which pass 3 groups with the others. Not where it
    only crosses its earlier ink: coming from one side of it and leaving to the other (a
    loop that crosses its own stroke at a narrow angle and goes on, a cursive l, e or h:
    one line through its crossing).

    >>> t = np.linspace(0, 4 * np.pi, 200)  # round twice
    >>> ring = np.stack([np.cos(t), np.sin(t)], axis=1)
    >>> [len(p) for p in cut_where_it_returns(ring, 0.2, 0.9)]  # turns, and the overlap
    [98, 98, 6]
    >>> up, down = np.array([0.17, 0.98]), np.array([-0.17, 0.98])  # 20 degrees apart
    >>> t = np.linspace(0, np.pi, 30)[:, None]
    >>> top = np.hstack([0.17 * np.cos(t), 0.98 + 0.17 * np.sin(t)])
    >>> ell = resample_polyline(np.vstack([-0.5 * up, up, top, down, -0.5 * down]), 0.01)
    >>> len(cut_where_it_returns(ell, 0.05, 0.9))  # up, round the top, down across
    1
    """
    out = []
    while len(points) >= 4:
        k = _first_return(points, reach, along_cos, back)
        if k is None:
            break
        out.append(points[:k + 1])
        points = points[k:]
    if len(points) >= 2:
        if out and arc_lengths(points)[-1] <= reach:  # a crumb: the last turn's end
            out[-1] = np.concatenate([out[-1], points[1:]])
        else:
            out.append(points)
    return out


#: points asked about at once (a stroke shaking over itself has many ink pairs near each)
CHUNK = 1024


def _cannot_return(points: np.ndarray, back: float) -> bool:
    """Whether every step of the polyline heads along its chord by more than 1 / ``back``
    of its length: then ink ``back`` reaches back along it lies more than a reach away
    along the chord alone, and nothing comes back (most strokes; no query needed)."""
    step = np.diff(points, axis=0)
    length = np.hypot(step[:, 0], step[:, 1])
    chord = points[-1] - points[0]
    span = float(np.hypot(*chord))
    if span <= 0:
        return False
    moving = length > 0
    return bool((step[moving] @ (chord / span) > length[moving] / back).all())


def _first_return(points: np.ndarray, reach: float, along_cos: float, back: float
                  ) -> int | None:
    """The first point that comes back along the polyline's earlier ink (see
    :func:`cut_where_it_returns`), asked about a chunk at a time, or None. Each stretch
    that comes within ``reach`` of the earlier ink (gaps shorter than ``reach`` bridged)
    is judged whole: it comes back where it runs along that ink somewhere in it (its
    course over ``reach``, not its shake from point to point), unless it crossed the ink
    (:func:`_across`)."""
    s = arc_lengths(points)
    if s[-1] <= back * reach or _cannot_return(points, back):
        return None
    segs = Segments.of([points])
    n = len(points)
    # its course over reach, not its shake from point to point
    ahead = np.minimum(np.searchsorted(s, s + 0.5 * reach), n - 1)
    behind = np.maximum(np.searchsorted(s, s - 0.5 * reach), 0)
    tan = points[ahead] - points[behind]
    tan /= np.maximum(np.hypot(tan[:, 0], tan[:, 1]), 1e-300)[:, None]
    onto = np.full(n, -1)  # the nearest earlier segment each point comes back near
    along = np.zeros(n, bool)  # ... and whether it runs along one of them
    judged = 0  # the stretches before this point are judged: none came back
    for start in range(0, n, CHUNK):
        rows = np.arange(start, min(start + CHUNK, n))
        i, seg = segs.running_along(points[rows], tan[rows], reach, 0.0)
        i = rows[i]
        far_back = s[i] - s[seg + 1] > back * reach
        i, seg = i[far_back], seg[far_back]
        v = segs.vector[seg]
        cos = np.abs((v * tan[i]).sum(axis=1)) / np.hypot(v[:, 0], v[:, 1])
        along[i[cos >= along_cos]] = True
        gap = segment_distance(points[i], segs.origin[seg], segs.end[seg])
        order = np.lexsort((gap, i))[::-1]  # the nearest last: it wins the assignment
        onto[i[order]] = seg[order]
        # the stretches that end a reach or more before the points asked so far
        asked = rows[-1] + 1
        known = n if asked == n else int(np.searchsorted(s, s[rows[-1]] - reach))
        found, judged = _came_back(points, s, onto[:asked], along, judged, known, reach,
                                   back)
        if found is not None:
            return found
    return None


def _came_back(points: np.ndarray, s: np.ndarray, onto: np.ndarray, along: np.ndarray,
               lo: int, hi: int, reach: float, back: float) -> tuple[int | None, int]:
    """The first point, in the stretches that end between ``lo`` and ``hi``, where the
    polyline came back along its earlier ink (``onto``: for each point asked so far, the
    earlier segment it comes near, -1 none; ``along``: whether it runs along one),
    judging each stretch that comes near whole, gaps shorter than ``reach`` bridged (the
    pen's shake); and where to go on judging from (the first stretch not yet ended)."""
    near = onto[lo:] >= 0
    for a, b in true_runs(~near):
        if a > 0 and b < len(near) - 1 and s[lo + b + 1] - s[lo + a - 1] < reach:
            near[a:b + 1] = True
    for first, last in true_runs(near):
        first, last = lo + first, lo + last
        if last >= hi - 1 and hi < len(points):
            return None, first  # it may go on: judged with the next points
        runs = np.flatnonzero(along[first:last + 1])
        if not len(runs):
            continue
        before = points[np.searchsorted(s, s[first] - back * reach):first]
        after = points[last + 1:np.searchsorted(s, s[last] + back * reach, side="right")]
        if not _across(points, s, before, after, onto[first], onto[last], reach):
            return first + int(runs[0]), hi  # it came back along there
    return None, hi


def _across(points: np.ndarray, s: np.ndarray, before: np.ndarray, after: np.ndarray,
            k: int, m: int, reach: float) -> bool:
    """Whether the polyline (arc lengths ``s``) crossed its own earlier ink where it came
    near it, from by its point ``k`` to by its point ``m``: its points ``before`` lie, on
    the whole, beyond half ``reach`` on one side of the earlier ink's course at ``k`` (its
    chord over ``reach`` each side), and its points ``after`` beyond it on the other side
    at ``m``. A pen's shake averages out over the points; a ring's second turn comes in
    along its first, from no side."""
    sides = []
    for stretch, j in ((before, k), (after, m)):
        if not len(stretch):
            return False
        chord = (points[np.searchsorted(s, s[j] + reach, side="right") - 1]
                 - points[np.searchsorted(s, s[j] - reach)])
        length = float(np.hypot(*chord))
        if length == 0:
            return False
        w = stretch - points[j]
        offset = float(np.mean(chord[0] * w[:, 1] - chord[1] * w[:, 0])) / length
        if abs(offset) <= 0.5 * reach:
            return False
        sides.append(offset > 0)
    return sides[0] != sides[1]


def run(work: Work) -> Work:
    store = getattr(work.memo, "pieces", None)
    got = store.get(work.merged) if store is not None else None
    if got is None:
        got = _cut(work)
        for array in (*got[0], got[1], got[2]):
            array.flags.writeable = False  # shared by every replay
        if store is not None:
            store.put(work.merged, got)
    pieces, owner, index = got
    return work.with_(pieces=list(pieces), piece_stroke=owner, piece_index=index)


def _cornered_legs(work: Work, drawn: list[int]) -> dict[int, list[np.ndarray]]:
    """Each ``drawn`` stroke resampled as its legs: cut at its corners
    (:func:`cut_at_corners`), but whole where it has a twin among the ``drawn`` ones,
    another stroke that, whole, lies along it as it lies along the other
    (:func:`core.lines.along.twinned`); at epsilon 0 every stroke whole. Twins are sought
    for the strokes with corners only: the others are whole either way."""
    if not work.merged:  # epsilon 0: each stroke comes back whole, as drawn
        return {k: [resample_polyline(work.strokes[k], work.h)] for k in drawn}
    t = work.tuning
    legs = {k: cut_at_corners(work.strokes[k], work.h, t.cut_angle, t.cut_reach * work.d,
                              t.round_share) for k in drawn}
    cornered = np.array([j for j, k in enumerate(drawn) if len(legs[k]) > 1], dtype=np.intp)
    twin = twinned([work.strokes[k] for k in drawn], cornered, t.twin_reach * work.d,
                   t.twin_share, work.h)
    for j in cornered[twin].tolist():
        legs[drawn[j]] = [resample_polyline(work.strokes[drawn[j]], work.h)]
    return legs


def _cut(work: Work) -> tuple[list[np.ndarray], np.ndarray, np.ndarray]:
    """The pieces of every input stroke, the stroke of each and its place in it. A stroke
    with a twin (:func:`_cornered_legs`) is not cut at its corners: both are passes of one
    line, corners and all, and its legs have their group already (its twin's); it is cut
    only where it comes back over itself."""
    drawn = [k for k, s in enumerate(work.strokes) if len(s) >= 2 and arc_lengths(s)[-1] > 0]
    legs_of = _cornered_legs(work, drawn)
    pieces, owner, index = [], [], []
    for k in drawn:
        cut = legs_of[k] if not work.merged else [
            turn for leg in legs_of[k]
            for turn in cut_where_it_returns(leg, work.tuning.follow_reach * work.d,
                                             work.tuning.follow_cos, work.tuning.back)]
        for j, piece in enumerate(cut):
            pieces.append(piece)
            owner.append(k)
            index.append(j)
    return pieces, np.asarray(owner, dtype=np.intp), np.asarray(index, dtype=np.intp)
