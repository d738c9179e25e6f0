"""Pass 2 of :mod:`core.lines`: what the agglomeration kept of each piece's ink. Every
sample of every piece is matched with the alive curve of the simplified complex nearest
to it among those within ``tuning.follow_reach`` d_eps that run along it (|cos| at least
``tuning.follow_cos``), and with where along that curve it comes nearest.

Why this carries the merges: before any merge each piece's samples lie on its own curves
(distance 0). A curve-curve merge replaces two curves by one between them; a patch merge
removes the curves between two patches, and nothing merged away lies farther than d_eps
from what remains (the distance guard). So the samples of pieces whose ink the merges
made one come to follow the same alive curve, and pieces left apart keep their own.

A slider's replays pass through states that share most alive curves, and a curve is the
same in every state it is alive in (curve ids follow the merge record). So a replay
starts from the nearest state followed before (:class:`Followed`, kept in the result's
memo) and follows again only the samples whose curve died or that lie within reach of a
curve born since: every other sample's nearest curve is unchanged, as the rest of what it
could follow is a subset of what it could follow then. Ties go to the lower curve id, then
the earlier segment along it, so that the answer is the same whichever way it is reached.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from ..arrays.geometry import Segments, nearest_of_each, tangents
from ..arrays.polylines import arc_lengths
from .work import Work

__all__ = ["Followed", "run"]

#: states followed kept for replays to start from (each two arrays of the samples)
KEPT_STATES = 4
#: samples asked about at once: the rows of a query (every segment within reach of each
#: sample, a few tens of bytes a row) stay within tens of MB however large the drawing
SAMPLES_AT_ONCE = 16384


@dataclass(frozen=True)
class Followed:
    """What pass 2 found in one state: its alive curves, and per sample the curve it
    follows and where along it (-1 and NaN: none)."""

    alive: frozenset[int]  #: the alive curves of two points or more
    curve: np.ndarray  #: (samples,) curve id per sample, -1 where none
    at: np.ndarray  #: (samples,) arc length along that curve, NaN where none


@dataclass
class FollowMemo:
    """The samples' points and tangents, and the states followed last (most recent last);
    one per set of pieces."""

    points: np.ndarray  #: (samples, 2) every piece's samples, end to end
    tangent: np.ndarray  #: (samples, 2) their unit tangents
    states: list[Followed]  #: the states followed last, at most ``KEPT_STATES``

    @cached_property
    def tree(self) -> shapely.STRtree:
        """The samples in a tree, made when a replay first asks which lie near a curve."""
        return shapely.STRtree(shapely.points(self.points))


def _nearest_along(state, alive: list[int], points: np.ndarray, tangent: np.ndarray,
                   work: Work) -> tuple[np.ndarray, np.ndarray]:
    """The alive curve each of ``points`` follows (-1: none) and where along it (see the
    module)."""
    curve = np.full(len(points), -1, dtype=np.intp)
    at = np.full(len(points), np.nan)
    if not alive or not len(points):
        return curve, at
    polylines = [state.curves[c] for c in alive]
    segs = Segments.of(polylines)
    # the arc length along its curve at each segment's first point
    sizes = np.fromiter(map(len, polylines), dtype=np.intp, count=len(polylines))
    ends = np.cumsum(sizes)
    running = arc_lengths(np.concatenate(polylines), ends - sizes, ends - 1)
    ids = np.asarray(alive)
    for start in range(0, len(points), SAMPLES_AT_ONCE):  # each sample on its own
        part = slice(start, start + SAMPLES_AT_ONCE)
        i, seg = segs.running_along(points[part], tangent[part],
                                    work.tuning.follow_reach * work.d, work.tuning.follow_cos)
        mine = points[part][i]
        v = segs.vector[seg]
        u = segs.along(seg, mine)
        foot = segs.origin[seg] + v * (u / np.hypot(v[:, 0], v[:, 1]))[:, None]
        # nearest first; ties by segment, in the order of curve ids: the same in every state
        pick = nearest_of_each(i, np.hypot(*(mine - foot).T), seg)
        i, seg, u = i[pick] + start, seg[pick], u[pick]
        curve[i] = ids[segs.polyline[seg]]
        at[i] = running[segs.start[seg]] + u
    return curve, at


def _memo_of(work: Work) -> FollowMemo:
    store = getattr(work.memo, "follow", None)
    got = store.get(work.merged) if store is not None else None
    if got is None:
        points = np.concatenate(work.pieces)
        tangent = np.concatenate([tangents(p) for p in work.pieces])
        got = FollowMemo(points, tangent, [])
        if store is not None:
            store.put(work.merged, got)
    return got


def run(work: Work) -> Work:
    state = work.state
    alive = [c for c in state.alive_curves() if len(state.curves[c]) >= 2]
    n = int(work.piece_sizes().sum())
    if not alive or not n:
        return work.with_(sample_curve=np.full(n, -1, dtype=np.intp),
                          sample_at=np.full(n, np.nan))
    memo = _memo_of(work)
    now = frozenset(alive)
    before = min(memo.states, key=lambda f: len(f.alive ^ now), default=None)
    if before is None or len(before.alive ^ now) >= len(now):
        curve, at = _nearest_along(state, alive, memo.points, memo.tangent, work)
    else:  # again only where a curve died or one was born within reach
        born = sorted(now - before.alive)
        dirty = np.isin(before.curve, sorted(before.alive - now))
        if born:
            segs = Segments.of([state.curves[c] for c in born])
            reach = work.tuning.follow_reach * work.d
            lo = np.minimum(segs.origin, segs.end) - reach
            hi = np.maximum(segs.origin, segs.end) + reach
            _, near = memo.tree.query(shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]))
            dirty[near] = True
        redo = np.flatnonzero(dirty)
        curve, at = before.curve.copy(), before.at.copy()
        curve[redo], at[redo] = _nearest_along(state, alive, memo.points[redo],
                                               memo.tangent[redo], work)
    curve.flags.writeable = at.flags.writeable = False  # kept, and handed on as they are
    memo.states = [f for f in memo.states if f.alive != now][-(KEPT_STATES - 1):] + [
        Followed(now, curve, at)]
    return work.with_(sample_curve=curve, sample_at=at)
