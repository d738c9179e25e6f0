"""Corners for the complex stage: two free ends that both stop short of the corner they
draw meet there."""

from __future__ import annotations

import numpy as np
import shapely

from ..arrays.geometry import unit_rows
from ..arrays.polylines import resample_polyline
from ..lines.junctions import Meets, cut_to, tip_of

__all__ = ["meet_at_corners"]


def meet_at_corners(lines: list[np.ndarray], closed: list[bool], meets: list[Meets],
                    reach: float, cos_max: float, spacing: float
                    ) -> tuple[list[np.ndarray], list[Meets]]:
    """``lines`` with each two free ends that stop short of the corner they draw meeting
    there: where the two lines carried on along their ends' directions cross, each at most
    ``reach`` on, at an angle (|cos| at most ``cos_max``); the nearest such corner first,
    each end once. An L whose two lines both stop short (a roof's two sides short of its
    top) is no end near a line, so :func:`meet_at_junctions` leaves it open.

    Args:
        lines, closed: as :func:`meet_at_junctions` gives them.
        meets: which line each end meets already (a free end: None).
        reach: how far each end may be carried on to the corner.
        cos_max: two ends nearly in line are no corner.
        spacing: a line whose end moved is resampled to this.

    Returns:
        The lines and what their ends meet, as :func:`meet_at_junctions`.

    >>> left = np.array([[0.0, 0.0], [4.0, 4.0]])  # a roof whose top is left open
    >>> right = np.array([[6.0, 4.0], [10.0, 0.0]])
    >>> out, meets = meet_at_corners([left, right], [False, False], [(None, None)] * 2,
    ...                              2.0, 0.87, 0.5)
    >>> out[0][-1].tolist(), out[1][0].tolist(), meets
    ([5.0, 5.0], [5.0, 5.0], [(None, 1), (0, None)])
    """
    free = [(k, end) for k, (pts, c, met) in enumerate(zip(lines, closed, meets))
            if not c and len(pts) >= 2 for end in (0, 1) if met[end] is None]
    if len(free) < 2:
        return lines, meets
    line_of = np.array([k for k, _ in free])
    at = np.array([lines[k][0] if end == 0 else lines[k][-1] for k, end in free])
    tips = [tip_of(lines[k], end, reach) for k, end in free]
    way = unit_rows(np.array([tip[0] - tip[-1] for tip in tips]))  # out of each line
    i, j = shapely.STRtree(shapely.points(at)).query(shapely.points(at), predicate="dwithin",
                                                     distance=2 * reach)
    keep = (i < j) & (line_of[i] != line_of[j])
    i, j = i[keep], j[keep]
    corners = []
    for a, b in zip(i.tolist(), j.tolist()):
        if abs(float(way[a] @ way[b])) > cos_max:
            continue
        # at[a] + s * way[a] == at[b] + t * way[b]
        s_t = np.linalg.solve(np.column_stack([way[a], -way[b]]), at[b] - at[a])
        if np.all(s_t >= 0) and np.all(s_t <= reach):
            corners.append((float(s_t.max()), a, b, at[a] + s_t[0] * way[a]))
    done: set[int] = set()
    out, met = list(lines), [list(m) for m in meets]
    for _, a, b, corner in sorted(corners, key=lambda c: (c[0], c[1], c[2])):
        if a in done or b in done:
            continue
        done.update((a, b))
        for x, y in ((a, b), (b, a)):
            k, end = free[x]
            out[k] = cut_to(out[k], end, corner, reach)
            met[k][end] = free[y][0]
    for k in {free[x][0] for x in done}:
        out[k] = resample_polyline(out[k], spacing)
    return out, [(m[0], m[1]) for m in met]
