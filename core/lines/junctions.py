"""Pass 9 of :mod:`core.lines`: junctions taken from the fitted lines. An open line's end
that stops within ``tuning.snap`` d_eps of another line, meeting it at an angle (more than
the merge angle), meets it exactly: an end short of the line is carried straight on to
it where that meets it within ``tuning.overshoot`` d_eps (a T, or an L where the other
line ends there too), else joined straight to its nearest point where that turns by at
most ``tuning.meet_turn`` (a corner), else bent gently onto it (over ``tuning.meet_bend``
times the gap: a segment turning back would be a hook no pen drew); an end that crosses
it and runs on by at most ``tuning.overshoot`` d_eps is cut at the crossing where the
other line, too, ends within that of it (a corner drawn with overshoots, an L); past the
middle of a line (a fin's edge drawn on over the body, an eave past the wall) it is left
where its ink ends. Lines that cross farther from their ends go straight through:
nothing here moves them. Fitting Beziers
(pass 10) moves a line a little, so after the fit each end that met a line is moved again
onto that line's curve (:func:`met_ends`). Not at epsilon 0, which keeps every stroke as
drawn. Here d_eps is at least ``tuning.meet_alpha`` (:attr:`Work.meet_d`): a dense
drawing's narrower width keeps its close lines apart, not its ends off the lines they
meet.

Invariant: only ends and the stretch bent onto a line move, each point by at most
``over``; a line never gains or loses more than that at an end.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import shapely

from ..arrays.geometry import lines_from, unit_rows
from ..arrays.polylines import arc_lengths, resample_polyline
from ..curves.bezier import SAMPLES_PER_SEGMENT, sample_bezier
from ..params import Tuning
from .work import Line, Work

__all__ = ["Meeting", "Meets", "cut_to", "meet_at_junctions", "met_ends", "run", "tip_of"]

#: which line each end of a line meets: (first end's, last end's), None for a free end
Meets = tuple[int | None, int | None]


def tip_of(points: np.ndarray, end: int, reach: float) -> np.ndarray:
    """The part of a polyline within ``reach`` (arc length) of one end, from that end."""
    pts = points if end == 0 else points[::-1]
    s = arc_lengths(pts)
    k = max(2, int(np.searchsorted(s, reach, side="right")))
    return pts[:k]


def cut_to(points: np.ndarray, end: int, at: np.ndarray, reach: float) -> np.ndarray:
    """The polyline with its ``end`` moved to ``at``: cut there if ``at`` lies on its last
    ``reach``, else extended to it. Oriented as given.

    >>> line = np.array([[0.0, 0.0], [2.0, 0.0]])
    >>> cut_to(line, 1, np.array([1.5, 0.0]), 1.0).tolist()  # cut back
    [[0.0, 0.0], [1.5, 0.0]]
    >>> cut_to(line, 0, np.array([-0.5, 0.0]), 1.0).tolist()  # extended
    [[-0.5, 0.0], [0.0, 0.0], [2.0, 0.0]]
    """
    pts = points if end == 1 else points[::-1]
    s = arc_lengths(pts)
    line = shapely.LineString(pts)
    t = float(shapely.line_locate_point(line, shapely.Point(at)))
    if s[-1] - t <= reach and np.hypot(*(shapely.get_coordinates(
            shapely.line_interpolate_point(line, t))[0] - at)) <= 1e-9 + 1e-6 * reach:
        keep = pts[s < t]
        out = np.concatenate([keep, [at]]) if len(keep) else np.stack([pts[0], at])
    else:
        out = np.concatenate([pts, [at]])
    return out if end == 1 else out[::-1]


@dataclass(frozen=True)
class Meeting:
    """How :func:`meet_at_junctions` meets ends with lines (lengths in the lines' frame).

    >>> Meeting.of(Tuning(), 0.01, 30.0, 0.0025).reach
    0.01
    """

    #: the widest gap an end is extended across
    reach: float
    #: the longest overshoot cut back
    over: float
    #: an end running along the other line (|cos| above this) is no junction
    cos_max: float
    #: a line whose end moved is resampled to this
    spacing: float
    #: whether an overshoot at a corner is cut back (an end crossing a line within ``over``
    #: of it, where that line also ends within ``over``: :func:`_near_an_end`); else an end
    #: that crosses a line is left as drawn, and only ends short of a line move
    cut: bool = True
    #: the other line's direction at a foot is taken over this share of ``reach`` each side
    tangent: float = Tuning.meet_tangent
    #: a line no longer than this many ``over`` is left as it is
    trim_length: float = Tuning.trim_length
    #: an end whose straight join would turn by more than the turn of ``cos_turn`` is
    #: bent onto the line's nearest point over this many times its gap (0: joined straight)
    bend: float = Tuning.meet_bend
    #: cosine of the turn above which a straight join to the nearest point is bent instead
    cos_turn: float = float(np.cos(np.radians(Tuning.meet_turn)))

    @classmethod
    def of(cls, tuning: Tuning, d: float, angle: float, spacing: float) -> Meeting:
        """Pass 9's meeting at bundle width ``d`` and merge angle ``angle`` (degrees)."""
        return cls(tuning.snap * d, tuning.overshoot * d, float(np.cos(np.radians(angle))),
                   spacing, True, tuning.meet_tangent, tuning.trim_length,
                   tuning.meet_bend, float(np.cos(np.radians(tuning.meet_turn))))


def bend_to(points: np.ndarray, end: int, at: np.ndarray, length: float) -> np.ndarray:
    """The polyline with its ``end`` moved to ``at`` by bending its last ``length`` (arc
    length; at most half the line): each point there moves by the end's shift times a
    weight falling smoothly from 1 at the end to 0 (a raised cosine), so the line turns
    gently onto ``at`` instead of gaining a segment at an angle. Nothing moves farther
    than the end does.

    >>> line = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0]])
    >>> bend_to(line, 1, np.array([4.0, 0.5]), 2.0)[:, 1].round(3).tolist()
    [0.0, 0.0, 0.0, 0.25, 0.5]
    """
    pts = points if end == 1 else points[::-1]
    s = arc_lengths(pts)
    span = min(length, 0.5 * s[-1])
    u = s[-1] - s  # distance from the end along the line
    w = np.where(u < span, 0.5 * (1.0 + np.cos(np.pi * u / max(span, 1e-300))), 0.0)
    out = pts + w[:, None] * (at - pts[-1])[None]
    out[-1] = at
    return out if end == 1 else out[::-1]


def _near_an_end(line: shapely.LineString, points: np.ndarray, over: float) -> bool:
    """Whether any of ``points`` (on the open ``line``) lies within ``over`` of one of its
    ends, along it: two lines that each run on past the other there cross at a corner
    drawn with overshoots (an L), not where one runs on over the other's middle (a T
    drawn past its bar, an X near an end).

    >>> bar = shapely.LineString([(0.0, 0.0), (10.0, 0.0)])
    >>> _near_an_end(bar, np.array([[9.5, 0.0]]), 1.0)
    True
    >>> _near_an_end(bar, np.array([[5.0, 0.0]]), 1.0)
    False
    """
    if line.is_ring:
        return False
    at = shapely.line_locate_point(line, shapely.points(points))
    return bool(np.any((at <= over) | (at >= line.length - over)))


def _end_target(points: np.ndarray, end: int, others: np.ndarray, how: Meeting
                ) -> tuple[np.ndarray, int, bool] | None:
    """Where one end should meet one of the ``others`` (shapely lines), which of them, and
    whether the end is bent there (else cut or extended straight): the crossing nearest
    the end on its last ``over``, where ``cut`` and the other line ends near it too (a
    corner: :func:`_near_an_end`; else an end that crosses a line there is left as it
    is); else, for a line whose nearest point lies within ``reach``, where the
    end carried straight on meets it within ``over`` (extended), or that nearest point
    (joined straight, or bent where that would turn back). None where there is none, or
    the line runs along the other."""
    reach, over, cos_max, cut = how.reach, how.over, how.cos_max, how.cut
    e = points[0] if end == 0 else points[-1]
    tip = tip_of(points, end, over)
    direction = unit_rows((tip[0] - tip[-1])[None])[0]  # out of the line, at the end
    crossings = [shapely.get_coordinates(g)
                 for g in shapely.intersection(shapely.LineString(tip), others)]
    if any(len(c) and not (cut and _near_an_end(o, c, over))
           for o, c in zip(others, crossings)):
        return None  # it runs on past a line: left as drawn, its ink ends there
    best, best_gap = None, np.inf
    for which, (other, crossing) in enumerate(zip(others, crossings)):
        bent = False
        if len(crossing):
            target = crossing[np.argmin(np.hypot(*(crossing - e).T))]
        else:
            target = shapely.get_coordinates(shapely.shortest_line(shapely.Point(e),
                                                                   other))[1]
        gap = float(np.hypot(*(target - e)))
        if gap > (over if len(crossing) else reach) or gap >= best_gap:
            continue
        if not len(crossing):  # carried straight on, where it meets the line within over
            hit = shapely.get_coordinates(shapely.intersection(
                shapely.LineString([e, e + direction * over]), other))
            if len(hit):
                target = hit[np.argmin(np.hypot(*(hit - e).T))]
            else:  # a straight join turning more than a corner would be a hook: bent
                bent = gap > 0 and float((target - e) @ direction) < how.cos_turn * gap
        foot = float(shapely.line_locate_point(other, shapely.Point(target)))
        ahead = shapely.get_coordinates(shapely.line_interpolate_point(
            other, [max(foot - how.tangent * reach, 0.0),
                    min(foot + how.tangent * reach, other.length)]))
        along = unit_rows((ahead[1] - ahead[0])[None])[0]
        if abs(float(along @ direction)) > cos_max:  # running along it: no junction
            continue
        best, best_gap = (target, which, bent), gap
    return best


def meet_at_junctions(lines: list[np.ndarray], closed: list[bool], how: Meeting
                      ) -> tuple[list[np.ndarray], list[Meets]]:
    """``lines`` with each open end that stops near another line meeting it (see the
    module), and which line each end meets.

    Args:
        lines: (n, 2) polylines, evenly spaced ``how.spacing`` apart.
        closed: whether each line is a ring (its ends never move).
        how: the reach, the overshoot and the rest (:class:`Meeting`).

    Returns:
        The lines (those unchanged as given) and, for each, the lines its ends meet.

    >>> bar = np.array([[0.0, 0.0], [10.0, 0.0]])
    >>> stem = np.array([[5.0, 0.5], [5.0, 10.0]])  # stops 0.5 short of the bar
    >>> how = Meeting(reach=1.0, over=2.0, cos_max=0.87, spacing=0.5)
    >>> out, meets = meet_at_junctions([bar, stem], [False, False], how)
    >>> out[1][0].tolist(), meets
    ([5.0, 0.0], [(None, None), (0, None)])
    """
    geoms = lines_from(lines)
    tree = shapely.STRtree(geoms)
    out, meets = [], []
    for k, pts in enumerate(lines):
        met: list[int | None] = [None, None]
        if closed[k] or len(pts) < 2 or arc_lengths(pts)[-1] <= how.trim_length * how.over:
            out.append(pts)
            meets.append((None, None))
            continue
        moved = pts
        for end in (0, 1):
            e = moved[0] if end == 0 else moved[-1]
            near = sorted(j for j in tree.query(shapely.Point(e), predicate="dwithin",
                                                distance=how.over).tolist() if j != k)
            if not near:
                continue
            found = _end_target(moved, end, geoms[near], how)
            if found is not None:
                target, which, bent = found
                e_gap = float(np.hypot(*(target - e)))
                moved = (bend_to(moved, end, target, how.bend * e_gap) if bent and how.bend > 0
                         else cut_to(moved, end, target, how.over))
                met[end] = near[which]
        out.append(resample_polyline(moved, how.spacing) if moved is not pts else pts)
        meets.append((met[0], met[1]))
    return out, meets


def met_ends(fitted: list, meets: list[Meets]) -> list:
    """The fitted strokes (:class:`core.lines.bezier.FittedStroke`, dataclasses with
    ``points`` and ``bezier``) with each end that meets another stroke moved onto that
    stroke's fitted curve, its Bezier handle moved with it (the tangent kept), so that a T
    or an L meets exactly in the output."""
    out = list(fitted)
    if all(m is None for pair in meets for m in pair):
        return out
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
            out[k] = replace(out[k], points=sample_bezier(bezier, SAMPLES_PER_SEGMENT),
                             bezier=bezier)
    return out


def run(work: Work) -> Work:
    lines = work.current_lines()
    if not work.merged or len(lines) < 2:
        return work.with_(lines=lines)
    points, meets = meet_at_junctions(
        [ln.points for ln in lines], [ln.closed for ln in lines],
        Meeting.of(work.tuning, work.meet_d, work.params.angle, work.h))
    return work.with_(lines=[ln if pts is ln.points and met == (None, None)
                             else Line(pts, ln.closed, ln.members, met)
                             for ln, pts, met in zip(lines, points, meets)])
