"""Pass 9 of :mod:`core.lines`: each line smoothed between its corners and fitted with
piecewise cubic Beziers (:func:`core.output.to_strokes.fit_lines`, shared with the
complex stage), the fits kept by content for a slider's replays. Smoothing moves the
line an end met at a junction (pass 8) a little: each such end is moved again onto that
line's fitted curve, its Bezier handle moved with it (the tangent kept), so that a T or an
L meets exactly in the output."""

from __future__ import annotations

import shapely

from ..arrays.polylines import arc_lengths, resample_polyline
from ..complex.noding import GRID
from ..output.bezier import SAMPLES_PER_SEGMENT, sample_bezier
from ..output.to_strokes import FittedStroke, fit_lines
from .work import Work

__all__ = ["run"]


def _met(fitted: list[FittedStroke], meets: list[tuple[int | None, int | None]]
         ) -> list[FittedStroke]:
    """The fitted strokes with each end that meets another stroke moved onto it."""
    out = list(fitted)
    geoms = [shapely.LineString(f.points) for f in fitted]
    for k, pair in enumerate(meets):
        moved = False
        bezier = out[k].bezier.copy()
        for end, other in enumerate(pair):
            if other is None or other == k:
                continue
            at = 0 if end == 0 else len(bezier) - 1
            handle = 1 if end == 0 else len(bezier) - 2
            target = shapely.get_coordinates(shapely.shortest_line(
                shapely.Point(bezier[at]), geoms[other]))[1]
            shift = target - bezier[at]
            bezier[at] += shift
            bezier[handle] += shift
            moved = True
        if moved:
            out[k] = FittedStroke(sample_bezier(bezier, SAMPLES_PER_SEGMENT), bezier,
                                  out[k].closed)
    return out


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
    if any(m is not None for pair in meets for m in pair):
        fitted = _met(fitted, meets)
    return work.with_(fitted=fitted)
