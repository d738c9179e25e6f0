"""Pass 10 of :mod:`core.lines`: each line smoothed between its corners and fitted with
piecewise cubic Beziers (:func:`core.output.to_strokes.fit_lines`, shared with the
complex stage), the fits kept by content for a slider's replays. Smoothing moves the
line an end met at a junction (pass 9) a little: each such end is moved again onto that
line's fitted curve, its Bezier handle moved with it (the tangent kept), so that a T or an
L meets exactly in the output (:func:`core.output.junctions.met_ends`)."""

from __future__ import annotations

from ..arrays.polylines import arc_lengths, resample_polyline
from ..complex.noding import GRID
from .junctions import met_ends
from ..output.to_strokes import fit_lines
from .work import Work

__all__ = ["run"]


def run(work: Work) -> Work:
    lines, closed, number = [], [], {}
    current = work.current_lines()
    for k, line in enumerate(current):
        if len(line.points) < 2 or arc_lengths(line.points)[-1] <= GRID:  # a crumb
            continue
        number[k] = len(lines)
        lines.append(resample_polyline(line.points, work.h))
        closed.append(line.closed)
    fitted = fit_lines(lines, closed, work.params, work.memo)
    meets = [tuple(number.get(m) if m is not None else None for m in line.meets)
             for k, line in enumerate(current) if k in number]
    return work.with_(fitted=met_ends(fitted, meets))
