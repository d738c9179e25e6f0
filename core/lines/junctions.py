"""Pass 9 of :mod:`core.lines`: junctions taken from the fitted lines
(:func:`core.output.junctions.meet_at_junctions`, shared with the complex stage): an open
line's end that stops within ``tuning.snap`` d_eps of another line, meeting it at an angle
(more than the merge angle), meets it exactly, and an end that crosses it and runs on by
at most ``tuning.overshoot`` d_eps is cut at the crossing; lines that cross farther from
their ends go straight through. Not at epsilon 0, which keeps every stroke as drawn."""

from __future__ import annotations

import numpy as np

from ..output.junctions import meet_at_junctions
from .work import Line, Work

__all__ = ["run"]


def run(work: Work) -> Work:
    lines = work.current_lines()
    if not work.merged or len(lines) < 2:
        return work.with_(lines=lines)
    points, meets = meet_at_junctions(
        [ln.points for ln in lines], [ln.closed for ln in lines],
        work.tuning.snap * work.d, work.tuning.overshoot * work.d,
        float(np.cos(np.radians(work.params.angle))), work.h)
    return work.with_(lines=[ln if pts is ln.points and met == (None, None)
                             else Line(pts, ln.closed, ln.members, met)
                             for ln, pts, met in zip(lines, points, meets)])
