"""Pass 8 of :mod:`core.lines`: junctions taken from the fitted lines. An open line's end
that stops within ``tuning.snap`` d_eps of another line, meeting it at an angle (more than
the merge angle), meets it exactly: an end short of the line is extended onto its nearest
point (a T, or an L where the other line ends there too), and an end that crosses it and
runs on by at most ``tuning.overshoot`` d_eps is cut at the crossing. Lines that cross farther from
their ends go straight through: nothing here moves them. Not at epsilon 0, which keeps
every stroke as drawn."""

from __future__ import annotations

import numpy as np
import shapely

from ..arrays.geometry import lines_from, unit_rows
from ..arrays.polylines import arc_lengths, resample_polyline
from .chains import cut_to, tip_of
from .work import Line, Work

__all__ = ["run"]


def _end_target(points: np.ndarray, end: int, others: np.ndarray, reach: float,
                over: float, cos_max: float) -> tuple[np.ndarray, int] | None:
    """Where one end should meet one of the ``others`` (shapely lines): the crossing
    nearest the end on its last ``over``, else the nearest point within ``reach``, and
    which of ``others``; None where there is none, or the line runs along the other."""
    e = points[0] if end == 0 else points[-1]
    tip = tip_of(points, end, over)
    direction = unit_rows((tip[0] - tip[-1])[None])[0]  # out of the line, at the end
    best, best_gap = None, np.inf
    for which, other in enumerate(others):
        crossing = shapely.get_coordinates(shapely.intersection(shapely.LineString(tip),
                                                                other))
        if len(crossing):
            target = crossing[np.argmin(np.hypot(*(crossing - e).T))]
        else:
            target = shapely.get_coordinates(shapely.shortest_line(shapely.Point(e),
                                                                   other))[1]
        gap = float(np.hypot(*(target - e)))
        if gap > (over if len(crossing) else reach) or gap >= best_gap:
            continue
        foot = float(shapely.line_locate_point(other, shapely.Point(target)))
        ahead = shapely.get_coordinates(shapely.line_interpolate_point(
            other, [max(foot - reach / 4, 0.0), min(foot + reach / 4, other.length)]))
        along = unit_rows((ahead[1] - ahead[0])[None])[0]
        if abs(float(along @ direction)) > cos_max:  # running along it: no junction
            continue
        best, best_gap = (target, which), gap
    return best


def run(work: Work) -> Work:
    lines = work.current_lines()
    if not work.merged or len(lines) < 2:
        return work.with_(lines=lines)
    reach = work.tuning.snap * work.d
    over = work.tuning.overshoot * work.d
    cos_max = float(np.cos(np.radians(work.params.angle)))
    points = [ln.points for ln in lines]
    geoms = lines_from(points)
    tree = shapely.STRtree(geoms)
    out = []
    for k, line in enumerate(lines):
        pts = points[k]
        if line.closed or arc_lengths(pts)[-1] <= 2 * over:
            out.append(line)
            continue
        meets = [None, None]
        for end in (0, 1):
            e = pts[0] if end == 0 else pts[-1]
            near = sorted(j for j in tree.query(shapely.Point(e), predicate="dwithin",
                                                distance=over).tolist() if j != k)
            if not near:
                continue
            found = _end_target(pts, end, geoms[near], reach, over, cos_max)
            if found is not None:
                pts = cut_to(pts, end, found[0], over)
                meets[end] = near[found[1]]
        if pts is not points[k]:  # evenly spaced again, its ends where they meet
            pts = resample_polyline(pts, work.h)
        out.append(Line(pts, False, line.members, (meets[0], meets[1])))
    return work.with_(lines=out)
