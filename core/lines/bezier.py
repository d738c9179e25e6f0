"""Pass 10 of :mod:`core.lines`: each line smoothed between its corners and fitted with
piecewise cubic Beziers (:func:`fit_lines`), the fits kept by content for a slider's
replays. Smoothing moves the
line an end met at a junction (pass 9) a little: each such end is moved again onto that
line's fitted curve, its Bezier handle moved with it (the tangent kept), so that a T or an
L meets exactly in the output (:func:`core.lines.junctions.met_ends`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arrays.polylines import arc_lengths, resample_polyline, total_lengths
from ..complex.noding import GRID
from ..curves.bezier import (
    SAMPLES_PER_SEGMENT,
    corner_indices,
    fit_beziers,
    sample_bezier,
    smooth_between_corners,
)
from ..curves.memo import StrokeMemo, shape_key
from ..params import SimplifyParams
from .junctions import met_ends
from .work import Work

__all__ = ["FittedStroke", "fit_lines", "run", "stroke_groups"]


@dataclass(frozen=True)
class FittedStroke:
    """One output stroke in the unit frame."""

    points: np.ndarray  # sampled polyline of the Bezier
    bezier: np.ndarray  # (3k + 1, 2) control points
    closed: bool


def _smoothed(pts: np.ndarray, closed: bool, params: SimplifyParams) -> np.ndarray:
    """A line sampled every ``tuning.sample`` d_eps, smoothed between its corners by
    ``params.smoothing`` d_eps (a sigma of smoothing / sample samples)."""
    if params.smoothing <= 0:
        return pts
    corners = corner_indices(pts, params.corner_angle, params.alpha,
                             params.tuning.round_share)
    return smooth_between_corners(pts, params.smoothing / params.tuning.sample, corners,
                                  closed)


def fit_lines(lines: list[np.ndarray], closed: list[bool], params: SimplifyParams,
              memo: StrokeMemo | None) -> list[FittedStroke]:
    """Each line (unit frame, evenly spaced) smoothed between its corners and fitted with
    piecewise cubic Beziers, all at once; ``params`` resolved. A fit is kept in ``memo``
    by the line before smoothing (smoothing depends on it and the params alone): a replay
    smooths and fits only the lines it has not seen."""
    memo = StrokeMemo() if memo is None else memo
    strokes = [(shape_key(pts, c), pts, c) for pts, c in zip(lines, closed)]
    fits = {key: memo.fits.get(key) for key, _, _ in strokes if key in memo.fits}
    todo = list({key: (pts, closed) for key, pts, closed in strokes if key not in fits}.items())
    if todo:  # fitted together
        made = fit_beziers([_smoothed(pts, closed, params) for _, (pts, closed) in todo],
                           params.fit_error * params.alpha, params.corner_angle,
                           [closed for _, (_, closed) in todo], params.tuning.round_share)
        for (key, _), bezier in zip(todo, made):
            fits[key] = (bezier, sample_bezier(bezier, SAMPLES_PER_SEGMENT))
            memo.fits.put(key, fits[key])
    return [FittedStroke(fits[key][1], fits[key][0], closed) for key, _, closed in strokes]



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
    drawn = [(number[k], p) for k, line in enumerate(current) if k in number
             for p in line.members]
    return work.with_(fitted=met_ends(fitted, meets),
                      groups=stroke_groups(drawn, work.piece_stroke,
                                           total_lengths(work.pieces), len(work.strokes)))


def stroke_groups(drawn: list[tuple[int, int]], piece_stroke: np.ndarray,
                  piece_length: np.ndarray, strokes: int) -> np.ndarray:
    """For each input stroke, the output stroke that draws most of its length, -1 where
    none does (its pieces were crumbs): the grouping the lines made, for measuring it
    against labels. ``drawn`` pairs each output stroke with a piece it stands for.

    >>> stroke_groups([(0, 0), (0, 1), (1, 2)], np.array([0, 1, 1, 2]),
    ...               np.array([1.0, 1.0, 3.0, 1.0]), 4).tolist()
    [0, 1, -1, -1]
    """
    out = np.full(strokes, -1, dtype=np.intp)
    if not drawn:
        return out
    line, piece = np.asarray(drawn, dtype=np.intp).T
    lines = int(line.max()) + 1
    # the length of each stroke each line draws, summed over the (stroke, line) pairs
    # drawn (not a strokes x lines table: 10,000 strokes and 3,000 lines would be 240 MB)
    pair, which = np.unique(piece_stroke[piece].astype(np.int64) * lines + line,
                            return_inverse=True)
    weight = np.bincount(which.ravel(), piece_length[piece], len(pair))
    stroke, line = pair // lines, pair % lines
    # each stroke's most, of equal ones the first line
    best = np.lexsort((line, -weight, stroke))
    best = best[np.r_[True, stroke[best][1:] != stroke[best][:-1]]]
    has = weight[best] > 0
    out[stroke[best][has]] = line[best][has]
    return out
