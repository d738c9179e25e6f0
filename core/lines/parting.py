"""Pass 9 of :mod:`core.lines`: one stretch of the drawing, one line. Where a line's end
runs along another line and then parts from it (a pass drawn along an edge that turns off
into a rounded corner; two strokes drawn from one point that fan apart), the stretch from
that end to where it parts is the other line drawn twice: the joint fit of pass 5 cannot
take it (the two part, so no one curve fits both), and each line keeps its own copy of the
stretch. That end stretch is cut off where the line parts, and the new end meets the other
line there (a T, or a Y), as the pen would have drawn it had it known.

An end stretch counts where it runs along the other line (within ``tuning.join_reach``
d_eps, where a joint fit keeps a line in place, and heading its way,
:meth:`core.arrays.geometry.Segments.running_along`) from within ``tuning.snap`` d_eps of
the end for at least ``tuning.crumb`` d_eps, the line going on for at least ``crumb`` past
it (shorter is a hook, pass 10's overshoot; a line wholly along another is pass 6's), and
the other line going on for at least ``crumb`` past where it parts (else the other is the
shorter copy: pass 6's, or one line drawn on, pass 5's); and only where the two inks leave
no band free of ink wider than ``params.fill_gap`` between them there (two lines drawn
close keep theirs, as in pass 5: :func:`core.lines.join.half_width`). The reach is the
join's, not a loose pass's (``member_reach``): two lines meeting at a shallow angle run
within a loose pass's reach of each other for several d_eps from where they meet, and
would be cut (docs/decisions.md). Where both lines'
ends run along each other from one place (a Y), the one that turns more where they part
is cut; where they overlap end to end (drawn on), neither: that is pass 5's join. Each
end is judged against the line it runs along longest, all ends at once on the lines as
pass 8 left them: no order of judging. Not at epsilon 0.

Invariant: only end stretches go, each leaving at least ``crumb`` d_eps of its line;
every point cut off lay within ``join_reach`` d_eps of a line that goes on past it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arrays.geometry import Segments, project_on, tangents
from ..arrays.polylines import arc_lengths, resample_polyline
from .fit import true_runs
from .join import half_width
from .work import Line, Work

__all__ = ["EndAlong", "ends_along", "run"]


@dataclass(frozen=True)
class EndAlong:
    """An end stretch of line ``line`` (its end ``end``: 0 first, 1 last) that runs along
    line ``other``: from sample ``first`` (counted from that end) to sample ``parts``,
    where it parts."""

    line: int
    end: int
    other: int
    first: int
    parts: int
    length: float


def _from_end(points: np.ndarray, end: int) -> np.ndarray:
    return points if end == 0 else points[::-1]


def ends_along(lines: list[Line], reach: float, start: float, least: float,
               along_cos: float) -> list[EndAlong]:
    """Each open line end's longest stretch along another line (see the module): from
    within ``start`` of the end, within ``reach`` of the other line and heading its way,
    at least ``least`` long, the line going on at least ``least`` past it.

    >>> x = np.linspace(0, 1, 21)[:, None]
    >>> bar = Line(np.hstack([2 * x - 0.5, 0 * x]), False, (0,))
    >>> fan = Line(np.hstack([x, np.maximum(0, x - 0.5)]), False, (1,))  # along, then up
    >>> [(e.line, e.end, e.other, e.parts) for e in ends_along([bar, fan], 0.02, 0.05,
    ...                                                          0.2, 0.9)]
    [(1, 0, 0, 9)]
    """
    if len(lines) < 2:
        return []
    pts = [ln.points for ln in lines]
    segs = Segments.of(pts)
    sizes = np.fromiter(map(len, pts), dtype=np.intp, count=len(pts))
    firsts = np.cumsum(sizes) - sizes
    which = np.repeat(np.arange(len(lines)), sizes)
    tan = np.concatenate([tangents(ln.points, ln.closed) for ln in lines])
    i, seg = segs.running_along(np.concatenate(pts), tan, reach, along_cos)
    other = segs.polyline[seg]
    keep = other != which[i]
    key = np.unique(i[keep].astype(np.int64) * len(lines) + other[keep])
    sample, other = key // len(lines), key % len(lines)
    found = []
    for k in np.unique(which[sample]).tolist():
        line = lines[k]
        s = arc_lengths(line.points)
        if line.closed or s[-1] < 2 * least:
            continue
        mine = which[sample] == k
        for o in np.unique(other[mine]).tolist():
            near = np.zeros(len(line.points), bool)
            near[sample[mine & (other == o)] - firsts[k]] = True
            for end in (0, 1):
                runs = true_runs(_from_end(near, end))
                if not runs:
                    continue
                a, b = runs[0]
                s_end = s if end == 0 else s[-1] - s[::-1]
                if (s_end[a] > start or s_end[b] - s_end[a] < least
                        or s_end[-1] - s_end[b] < least):
                    continue
                found.append(EndAlong(k, end, o, a, b, float(s_end[b] - s_end[a])))
    best: dict[tuple[int, int], EndAlong] = {}
    for e in found:
        held = best.get((e.line, e.end))
        if held is None or (e.length, -e.other) > (held.length, -held.other):
            best[(e.line, e.end)] = e
    return [best[key] for key in sorted(best)]


def _turn(line: Line, e: EndAlong, least: float) -> float:
    """How far line ``e.line`` turns where it parts: 1 - cos between the stretch along the
    other line and its next ``least`` of length."""
    pts = _from_end(line.points, e.end)
    s = arc_lengths(pts)
    on = int(np.searchsorted(s, s[e.parts] + least))
    on = min(on, len(pts) - 1)
    before, after = pts[e.parts] - pts[e.first], pts[on] - pts[e.parts]
    norm = max(float(np.hypot(*before) * np.hypot(*after)), 1e-300)
    return 1.0 - float(before @ after) / norm


def run(work: Work) -> Work:
    lines = work.current_lines()
    if not work.merged or len(lines) < 2:
        return work.with_(lines=lines)
    t = work.tuning
    reach, least = t.join_reach * work.d, t.crumb * work.d
    found = ends_along(lines, reach, t.snap * work.d, least, t.follow_cos)
    if not found:
        return work.with_(lines=lines)
    widths: dict = {}
    by_pair: dict[tuple[int, int], list[EndAlong]] = {}
    for e in found:
        by_pair.setdefault((e.line, e.other), []).append(e)
    cuts: list[EndAlong] = []
    for e in found:
        pts = _from_end(lines[e.line].points, e.end)
        stretch = pts[e.first:e.parts + 1]
        on = project_on(lines[e.other].points, stretch[[0, -1]])
        ahead = on.length - on.at[1] if on.at[1] >= on.at[0] else on.at[1]
        if ahead < least:
            continue  # the other line stops where this one parts: the shorter one is the
            # copy (pass 6's, or one line drawn on: pass 5's)
        gap = float(np.median(project_on(lines[e.other].points, stretch).distance))
        if (gap - half_width(lines[e.line], work, widths)
                - half_width(lines[e.other], work, widths) > work.params.fill_gap):
            continue  # two lines drawn close: a band of paper between their inks
        back = by_pair.get((e.other, e.line), [])
        if back:
            f = back[0]
            tip = np.hypot(*(pts[0] - _from_end(lines[f.line].points, f.end)[0]))
            if tip > 0.5 * min(e.length, f.length):
                continue  # overlapping end to end: drawn on, pass 5's
            mine, theirs = _turn(lines[e.line], e, least), _turn(lines[f.line], f, least)
            if (theirs, lines[f.line].length, f.line) > (mine, lines[e.line].length, e.line):
                continue  # a Y: the other one turns off, and is cut
        cuts.append(e)
    if not cuts:
        return work.with_(lines=lines)
    out = list(lines)
    for k in sorted({e.line for e in cuts}):
        out[k] = _trimmed(lines[k], [e for e in cuts if e.line == k], lines, work.h)
    return work.with_(lines=out)


def _trimmed(line: Line, cuts: list[EndAlong], lines: list[Line], h: float) -> Line:
    """``line`` without its end stretches ``cuts``, each new end on the nearest point of
    the other line to where it parts, the samples within that distance past the parting
    point left out (no kink where it leaves the other line); of two that would leave
    nothing between them, the longer stretch goes. Resampled to ``h``."""
    pts, n = line.points, len(line.points)
    s = arc_lengths(pts)
    keep = [0, n]  # the samples kept: [keep[0], keep[1])
    feet: list[np.ndarray | None] = [None, None]
    meets = list(line.meets)
    for e in sorted(cuts, key=lambda e: (-e.length, e.end)):
        parts = e.parts if e.end == 0 else n - 1 - e.parts
        along = project_on(lines[e.other].points, pts[parts:parts + 1])
        if e.end == 0:
            first = int(np.searchsorted(s, s[parts] + float(along.distance[0]), "right"))
            if first >= keep[1] - 1:
                continue
            keep[0] = first
        else:
            last = int(np.searchsorted(s, s[parts] - float(along.distance[0]), "left"))
            if last <= keep[0] + 1:
                continue
            keep[1] = last
        feet[e.end] = _point_at(lines[e.other].points, float(along.at[0]))
        meets[e.end] = e.other
    middle = pts[keep[0]:keep[1]]
    new = np.concatenate([f[None] if f is not None else np.zeros((0, 2)) for f in feet[:1]]
                         + [middle]
                         + [f[None] if f is not None else np.zeros((0, 2))
                            for f in feet[1:]])
    return Line(resample_polyline(new, h), False, line.members, tuple(meets))


def _point_at(line: np.ndarray, at: float) -> np.ndarray:
    s = arc_lengths(line)
    k = int(np.clip(np.searchsorted(s, at, side="right") - 1, 0, len(line) - 2))
    u = (at - s[k]) / max(s[k + 1] - s[k], 1e-300)
    return line[k] + np.clip(u, 0.0, 1.0) * (line[k + 1] - line[k])
