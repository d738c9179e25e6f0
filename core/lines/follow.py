"""Pass 2 of :mod:`core.lines`: what the agglomeration kept of each piece's ink. Every
sample of every piece is matched with the alive curve of the simplified complex nearest
to it among those within ``tuning.follow_reach`` d_eps that run along it (|cos| at least
``tuning.follow_cos``), and with where along that curve it comes nearest.

Why this carries the merges: before any merge each piece's samples lie on its own curves
(distance 0). A curve-curve merge replaces two curves by one between them; a patch merge
removes the curves between two patches, and nothing merged away lies farther than d_eps
from what remains (the distance guard). So the samples of pieces whose ink the merges
made one come to follow the same alive curve, and pieces left apart keep their own.
"""

from __future__ import annotations

import numpy as np

from ..arrays.geometry import Segments, tangents
from ..arrays.polylines import arc_lengths
from .work import Work

__all__ = ["run"]


def run(work: Work) -> Work:
    state = work.state
    alive = [c for c in state.alive_curves() if len(state.curves[c]) >= 2]
    n = int(work.piece_sizes().sum())
    curve = np.full(n, -1, dtype=np.intp)
    at = np.full(n, np.nan)
    if not alive or not n:
        return work.with_(sample_curve=curve, sample_at=at)
    polylines = [state.curves[c] for c in alive]
    segs = Segments.of(polylines)
    # the arc length along its curve at each segment's first point
    running = np.concatenate([arc_lengths(p) for p in polylines])
    points = np.concatenate(work.pieces)
    tan = np.concatenate([tangents(p) for p in work.pieces])
    i, seg = segs.running_along(points, tan, work.tuning.follow_reach * work.d,
                                work.tuning.follow_cos)
    v = segs.vector[seg]
    length = np.hypot(v[:, 0], v[:, 1])
    u = segs.along(seg, points[i])
    foot = segs.origin[seg] + segs.vector[seg] * (u / length)[:, None]
    dist = np.hypot(*(points[i] - foot).T)
    order = np.lexsort((seg, dist, i))  # nearest first, ties by segment: deterministic
    i, seg, u = i[order], seg[order], u[order]
    first = np.ones(len(i), bool)
    first[1:] = i[1:] != i[:-1]
    i, seg, u = i[first], seg[first], u[first]
    curve[i] = np.asarray(alive)[segs.polyline[seg]]
    at[i] = running[segs.start[seg]] + u
    return work.with_(sample_curve=curve, sample_at=at)
