"""Pass 4 of :mod:`core.lines`: one centreline per group, fitted to all its pieces' ink
at once, and each group checked by its fit.

The centreline (StrokeStrip's view, simplified: a cluster's strokes parameterize along
one curve): a *spine* is grown from the group's longest piece, each other piece attached
where it runs within ``member_reach`` d_eps of it, its parts beyond the spine's ends
extending it where the piece heads the spine's way there (within ``tuning.cut_angle``; one
that crosses the end at a corner is another line; a piece that leaves one end and comes
back to the other closes it: a circle drawn as loose arcs; so does a spine whose own ends
meet, within ``member_reach`` and a ``tuning.loop_length``-th of its length: a small ring
drawn whole). Then, twice, the spine is moved to the median of the ink's offsets from it,
taken in bins ``tuning.bin`` d_eps long along it (a stray pass does not pull the line off
the others), and the line so moved is smoothed over ``tuning.smooth`` d_eps
(:func:`core.curves.bezier.smooth_between_corners`) between the corners the pen drew
(where the spine turns as pass 1 cuts a stroke and a pass turns so too there, not at a
flick near its end, nor where the spine steps from one pass onto the next: a shape drawn
round again keeps its corners): the line runs through the middle of the passes, and ends
where the ink ends. The line is smoothed, not the offsets alone: the spine is one pass,
and a line made of it plus smoothed offsets would keep that pass's own wander at every
scale the smoothing takes out of the offsets. A group of one piece is that piece,
resampled: there is no other ink to move it to (pass 10 smooths it as it smooths every
line).

The checks. First, a group whose passes fall into two bundles along the stretch they
share, one side's ink never crossing to the other's, with a band free of ink between them
that :func:`clear_band` says parts two lines along most of it (wider than the
drawing's usual spacing of passes, or than the inks beside it: two tight bundles, or
single strokes, drawn close), is split there (:func:`band_split`), each side fitted on its
own: the width is local, from the group's own ink; but not where it lies in open paper,
no other ink within a few bands of it, and its sides are not two bundles tighter than the
band (:func:`one_loose_line`): one loose line, however wide. Then a group two of whose
pieces (a pair of pass 3) run along each other and then part, each going on, is split
into the parts its pairs make with no such two in one part (:func:`parted`): two close
lines that part somewhere (a narrow fork, an edge along another for a while), however
their passes interleave where they run together; not a curl's or a loop's passes, which
wind in at their own rates. Then, a piece of which less than
``tuning.member_share`` lies within ``member_reach`` d_eps of its group's line does not
draw that line, and is split off; so is a piece the line leaves: it runs along the line
and then, from the line's middle (at least ``tuning.crumb`` d_eps from either end), away
from it for good, farther than ``member_reach`` along at least ``crumb``. The line turned
off onto other ink there (the spine grew along a pass that turns off an edge, and the
edge's passes go straight on); the piece draws another line, which comes out whole fitted
on its own, whereas as a member only its stretch beyond the turn would (pass 8's). The
pieces split off are grouped again among themselves (the components of pass 3's pairs
among them) and fitted the same way. A long chain of pairs (a line passing along a ring
for a while) joins pieces of several lines into one group; the fit takes them apart.

The helpers of passes 5 and 6 live here too (:func:`along_pairs`, :func:`regroup`,
:func:`absorb_lines`): they fit groups again.

Invariant: every piece's ink is stood for by exactly one line (its group's, or its own).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import shapely

from ..arrays.components import component_labels, kept_apart_labels
from ..arrays.geometry import Segments, project_on, tangents
from ..arrays.polylines import arc_lengths, ends_meet, resample_polyline, true_runs
from ..curves.bezier import corner_indices, smooth_between_corners
from ..params import Tuning
from .along import parting, runs_along
from .work import Line, Work

__all__ = ["GroupFit", "absorb_lines", "along_pairs", "band_split", "centreline",
           "clear_band", "components", "fit_group", "fitted_centreline", "group_fit",
           "lies_apart", "one_loose_line", "regroup", "run"]


def _runs_on_from(line: np.ndarray, run: np.ndarray, reach: float, cos_min: float) -> bool:
    """Whether ``run``, the stretch of a piece lying along ``line`` up to where the line
    ends, heads the way the line does there: the chord of its last ``reach`` turns from
    the chord of the line's last ``reach`` by less than the corner angle whose cosine is
    ``cos_min``. A piece that heads on along the line and then curls carries it on; one
    that only crosses the line's end (at a corner, or more) is another line, as pass 1
    cuts a stroke at a corner.

    >>> line = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> _runs_on_from(line, np.array([[1.0, 0.1], [2.0, 0.1]]), 1.0, 0.34)
    True
    >>> _runs_on_from(line, np.array([[2.0, -0.3], [2.0, 0.3]]), 1.0, 0.34)  # crosses it
    False
    """
    def chord(p: np.ndarray) -> np.ndarray:
        s = arc_lengths(p)
        return p[-1] - p[max(int(np.searchsorted(s, s[-1] - reach, side="right")) - 1, 0)]

    a, b = chord(line), chord(run)
    na, nb = np.hypot(*a), np.hypot(*b)
    return bool(na == 0 or nb == 0 or a @ b >= cos_min * na * nb)


def _attach(spine: np.ndarray, piece: np.ndarray, reach: float, end_zone: float,
            loop_length: float, cos_min: float) -> tuple[np.ndarray, bool] | None:
    """The spine with ``piece`` attached (see the module), and whether it closed; None
    where the piece does not run along it. The piece extends an end where it parts from
    the spine within ``end_zone`` of it heading the spine's way (:func:`_runs_on_from`
    with ``cos_min``), and closes the spine where it comes back within ``end_zone`` of the
    other end of a spine longer than ``loop_length``."""
    gap = np.maximum(0.0, np.maximum(piece.min(axis=0) - spine.max(axis=0),
                                     spine.min(axis=0) - piece.max(axis=0)))
    if np.hypot(*gap) > reach:  # their boxes lie farther apart than reach
        return None
    along = project_on(spine, piece)
    t, length, near = along.at, along.length, along.distance <= reach
    runs = true_runs(near)
    if not runs:
        return None
    a, b = max(runs, key=lambda r: (r[1] - r[0], -r[0]))
    if b == a:
        return None
    if t[b] < t[a]:  # drawn the other way
        piece, t, near = piece[::-1], t[::-1], near[::-1]
        a, b = len(piece) - 1 - b, len(piece) - 1 - a
    closed = False
    out = spine
    if b + 1 < len(piece) and t[b] >= length - end_zone:
        back = np.flatnonzero(near[b + 1:])
        tail = piece[b + 1:b + 1 + back[0]] if len(back) else piece[b + 1:]
        if _runs_on_from(spine, piece[a:b + 1], reach, cos_min):
            closed = bool(len(back) and t[b + 1 + back[0]] <= end_zone
                          and length > loop_length)
            out = np.concatenate([out, tail])
    if a > 0 and t[a] <= end_zone and not closed:
        back = np.flatnonzero(near[:a])
        head = piece[back[-1] + 1:a] if len(back) else piece[:a]
        if _runs_on_from(spine[::-1], piece[a:b + 1][::-1], reach, cos_min):
            closed = bool(len(back) and t[back[-1]] >= length - end_zone
                          and length > loop_length)
            out = np.concatenate([head, out])
    return out, closed


def _spine(pieces: list[np.ndarray], reach: float, h: float, end_zone: float,
           loop_length: float, cos_min: float) -> tuple[np.ndarray, bool]:
    order = sorted(range(len(pieces)), key=lambda k: (-len(pieces[k]), k))
    spine, closed = pieces[order[0]], False
    pending = order[1:]
    while pending and not closed:
        rest = []
        for k in pending:
            got = None if closed else _attach(spine, pieces[k], reach, end_zone,
                                              loop_length, cos_min)
            if got is None:
                rest.append(k)
                continue
            spine, closed = got
            spine = resample_polyline(spine, h) if len(spine) >= 2 else spine
        if len(rest) == len(pending):
            break
        pending = rest
    if not closed:
        closed = ends_meet(spine, reach, reach / loop_length)
    return spine, closed


def _bin_stats(bins: np.ndarray, values: np.ndarray, n: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Which of ``n`` bins hold values, and the lowest, the median and the highest of each
    (inf, 0 and -inf where none), from one sort.

    >>> has, low, middle, high = _bin_stats(np.array([0, 0, 0, 2]),
    ...                                     np.array([1.0, 9.0, 2.0, 4.0]), 3)
    >>> has
    array([ True, False,  True])
    >>> low, middle, high
    (array([ 1., inf,  4.]), array([2., 0., 4.]), array([  9., -inf,   4.]))
    """
    order = np.lexsort((values, bins))
    bins, values = bins[order], values[order]
    first = np.searchsorted(bins, np.arange(n), side="left")
    last = np.searchsorted(bins, np.arange(n), side="right")
    count = last - first
    has = count > 0
    low = first + (count - 1) // 2
    high = first + count // 2
    middle = np.zeros(n)
    middle[has] = 0.5 * (values[low[has]] + values[high[has]])
    lowest, highest = np.full(n, np.inf), np.full(n, -np.inf)
    lowest[has], highest[has] = values[first[has]], values[last[has] - 1]
    return has, lowest, middle, highest


def centreline(pieces: list[np.ndarray], reach: float, h: float, bin_length: float,
               smooth: float, *, end_zone: float = Tuning.end_zone,
               loop_length: float = Tuning.loop_length, corner: float = Tuning.cut_angle,
               corner_reach: float = 0.0, round_share: float = Tuning.round_share,
               rounds: int = 2
               ) -> tuple[np.ndarray, bool]:
    """The line through the middle of ``pieces`` (see the module), evenly spaced by ``h``,
    and whether it is closed (then its first point is repeated last). ``end_zone`` and
    ``loop_length`` are multiples of ``reach`` (:class:`core.params.Tuning`).

    >>> x = np.linspace(0, 1, 41)[:, None]
    >>> passes = [np.hstack([x, 0 * x + y]) for y in (-0.01, 0.0, 0.01)]
    >>> line, closed = centreline(passes, 0.02, 0.025, 0.025, 0.01)
    >>> closed, bool(np.abs(line[:, 1]).max() < 1e-9), line[[0, -1], 0].round(3).tolist()
    (False, True, [0.0, 1.0])
    """
    spine, closed = _spine(pieces, reach, h, end_zone * reach, loop_length * reach,
                           float(np.cos(np.radians(corner))))
    ink = np.concatenate(pieces)
    drawn = None  # the passes' own corners, found where the line has any
    for _ in range(rounds if len(pieces) > 1 else 0):  # one pass: the line is the pen's
        if closed:
            spine = np.concatenate([spine, spine[:1]]) if not np.array_equal(
                spine[0], spine[-1]) else spine
        line = resample_polyline(spine, min(h, bin_length))
        n = len(line)
        if n < 3:
            break
        tan = tangents(line, closed)
        normal = np.column_stack([-tan[:, 1], tan[:, 0]])
        along = project_on(line, ink)
        t, length, use = along.at, along.length, along.distance <= reach
        b = np.clip(np.rint(t / max(length, 1e-300) * (n - 1)).astype(np.intp), 0, n - 1)
        offset = ((ink - line[b]) * normal[b]).sum(axis=1)
        has, _, middle, _ = _bin_stats(b[use], offset[use], n)
        if not has.any():
            break
        k = np.arange(n)
        mean = np.interp(k, k[has], middle[has], period=n - 1 if closed else None)
        moved = line + normal * mean[:, None]  # the line through the middle of the ink
        if closed:
            moved[-1] = moved[0]
        corners = _corners(line, corner, corner_reach, round_share, closed)
        if corners:
            if drawn is None:
                drawn = _pen_corners(pieces, corner, corner_reach, round_share)
            corners = _drawn(line, corners, drawn, corner_reach)
        spine = smooth_between_corners(moved, smooth / (length / (n - 1)), corners, closed)
        if closed:  # a ring comes back with its first point repeated last
            spine = spine[:-1]
    if closed:
        spine = np.concatenate([spine, spine[:1]])
    return resample_polyline(spine, h), closed


def _corners(line: np.ndarray, angle: float, reach: float, round_share: float,
             closed: bool) -> list[int]:
    """Where the evenly spaced ``line`` turns as pass 1 cuts a stroke (more than ``angle``
    within ``reach`` each side, not round). Not within ``reach`` of an open line's ends: a
    turn read on a leg shorter than the test's window is a flick of the pen (a hook), not
    a corner (none with ``reach`` 0).

    >>> x = np.linspace(0, 1, 41)
    >>> ell = np.concatenate([np.c_[x, 0 * x], np.c_[1 + 0 * x[1:], x[1:]]])
    >>> _corners(ell, 70, 0.1, 0.5, False), _corners(ell[:44], 70, 0.1, 0.5, False)
    ([40], [])
    """
    if reach <= 0:
        return []
    found = corner_indices(line, angle, reach, round_share)
    if closed or not found:
        return found
    s = arc_lengths(line)
    return [k for k in found if reach <= s[k] <= s[-1] - reach]


def _pen_corners(pieces: list[np.ndarray], angle: float, reach: float, round_share: float
                 ) -> np.ndarray:
    """(k, 2): the corners of each of ``pieces`` itself (:func:`_corners`): where a pass
    turns as the pen drew it."""
    found = [p[_corners(p, angle, reach, round_share, False)] for p in pieces if len(p) > 2]
    return np.concatenate(found) if found else np.zeros((0, 2))


def _drawn(line: np.ndarray, corners: list[int], drawn: np.ndarray, reach: float
           ) -> list[int]:
    """The ``corners`` of ``line`` that a pass drew: with one of the passes' own corners
    (``drawn``) within ``reach``. A turn of the line alone is no corner: where the spine
    steps from one pass onto the next (a piece extends it a little aside), the line jogs
    and no pass turns, and the jog is smoothed away like any other wander.

    >>> jog = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.1], [2.0, 0.1]])
    >>> _drawn(jog, [1, 2], np.array([[1.0, 0.1]]), 0.05), _drawn(jog, [1], np.zeros((0, 2)), 0.05)
    ([2], [])
    """
    if not len(drawn):
        return []
    gap = np.hypot(*(line[corners][:, None, :] - drawn[None, :, :]).transpose(2, 0, 1))
    return [k for k, g in zip(corners, gap.min(axis=1)) if g <= reach]


def _signed_offsets(line: np.ndarray, points: np.ndarray, reach: float
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which ``points`` lie beside the evenly spaced open ``line`` (within ``reach``, not
    beyond its ends), how far along it, and their signed offsets from it (left of its
    direction positive)."""
    along = project_on(line, points)
    t, length = along.at, along.length
    n = len(line)
    beside = (along.distance <= reach) & (t > 0) & (t < length)
    b = np.clip(np.rint(t / max(length, 1e-300) * (n - 1)).astype(np.intp), 0, n - 1)
    tan = tangents(line)
    normal = np.column_stack([-tan[:, 1], tan[:, 0]])
    return beside, t, ((points - line[b]) * normal[b]).sum(axis=1)


def clear_band(band: float, spread: float, work: Work) -> bool:
    """Whether a band free of ink ``band`` wide between two inks, the wider of which spreads
    ``spread`` across, is wide enough to part two lines: wider than the drawing's usual
    spacing of passes (``params.fill_gap``), or than ``tuning.band_ratio`` times the inks
    beside it, and at least ``tuning.band_floor`` d_eps. Whether it does part them is
    :func:`one_loose_line`'s to say too."""
    t = work.tuning
    local = max(t.band_floor * work.d, t.band_ratio * spread)
    return bool(band > min(work.params.fill_gap, local))


def lies_apart(points: np.ndarray, own, reach: float, ink: Segments, share: float) -> bool:
    """Whether ``points`` lie apart from every polyline of ``ink`` but those numbered in
    ``own``: none lies within ``reach`` of at least ``share`` of the points.

    >>> ink = Segments.of([np.array([[0.0, 0.0], [4.0, 0.0]]), np.array([[0.0, 1.0], [1.0, 1.0]])])
    >>> pts = np.array([[0.0, 0.1], [1.0, 0.1], [2.0, 0.1], [3.0, 0.1]])
    >>> lies_apart(pts, [0], 1.0, ink, 0.5)  # the other lies near a quarter of them
    True
    >>> lies_apart(pts, [0], 1.0, ink, 0.8)
    False
    """
    most = (1 - share) * len(points)  # points with other ink near, at most
    near = 0
    tree, number = ink.whole  # which polylines come near, not which of their segments
    for half in (points[0::2], points[1::2]):  # the second half asked only where the
        i, k = tree.query(shapely.points(half), predicate="dwithin", distance=reach)
        near += len(np.unique(i[~np.isin(number[k], own)]))  # first leaves it open
        if near > most:
            return False
    return True


def one_loose_line(band: float, spread: float, bundles: bool, points: np.ndarray, own,
                   work: Work) -> bool:
    """Whether two inks with a band ``band`` wide between them are one loose line however
    wide the band (the passes of one line drawn in open paper, the issue's "nothing else
    near"): they are not two bundles tighter than the band (``bundles``: each side two
    passes or more, the band wider than ``tuning.tight_ratio`` times the wider side's
    ``spread``), and they lie apart from all other ink (:func:`lies_apart`: no piece but
    those in ``own`` within ``tuning.apart`` times the band of ``tuning.apart_share`` of
    ``points``, their ink). The context StrokeAggregator judges a pair by: a band is a
    space between two lines where other lines lie as close; alone, it is a loose hand.
    Never where ``params.fill_gap`` is 0 (no band lies inside one bundle)."""
    t = work.tuning
    if work.params.fill_gap == 0 or (bundles and band > t.tight_ratio * spread):
        return False  # fill_gap 0: no band lies inside one bundle
    reach = t.apart * band  # asked every half reach along the ink (its points lie h apart)
    return lies_apart(points[::max(1, int(reach / (2 * work.h)))], own, reach, work.ink,
                      t.apart_share)


def band_split(pieces: list[np.ndarray], reach: float, step: float, clear,
               share: float = 0.0, samples: int = Tuning.band_samples
               ) -> tuple[list[int], list[int]] | None:
    """The pieces (indices) either side of a band free of ink that parts the passes
    beside the longest piece into two lines, where ``clear(band, spread, sides)`` says it
    does (``sides``: the judged pieces on each side); None where no band does (one line,
    however loosely drawn).

    The pieces beside the longest (within ``reach``, ``samples`` or more) are ordered
    across it by their median offset from it; each place in that order is judged in
    stretches ``step`` long along it where ink lies on both sides: the band is the space
    between the two sides' ink there, ``spread`` the wider side's width there. Two lines
    are two bundles along their shared stretch: one side's ink stays on its side (its
    median offset beyond the other's in every stretch: loose passes of one line wander
    across each other), and the band is clear along most of it (``clear`` of the band's
    lower quartile over the stretches and of the median spread): a stray point, or two
    lines meeting at a junction, does not close it; passes that touch along a quarter of
    their way do. The sides must lie beside each other over at least ``share`` of the
    length of the shorter side's longest piece, two stretches or more (passes drawn on
    from one another overlap only at their ends). Of the places that part, the widest
    band's (its lower quartile). A piece not beside the longest goes with the longest's
    side.

    >>> x = np.linspace(0, 1, 41)[:, None]
    >>> two = [np.hstack([x, 0 * x + y]) for y in (0.0, 0.001, 0.02, 0.021)]
    >>> band_split(two, 0.05, 0.1, lambda band, *_: band > 0.01)
    ([0, 1], [2, 3])
    >>> band_split(two, 0.05, 0.1, lambda band, *_: band > 0.03) is None
    True
    >>> crossing = [two[0], np.hstack([x, 0.03 * x - 0.015])]  # it crosses the first
    >>> band_split(crossing, 0.05, 0.1, lambda band, *_: band > 0.005) is None
    True
    >>> meeting = [two[0], np.hstack([x, 0.02 * x])]  # a narrow V: two lines meeting
    >>> band_split(meeting, 0.05, 0.1, lambda band, *_: band > 0.004)
    ([0], [1])
    """
    root = max(range(len(pieces)), key=lambda k: (len(pieces[k]), -k))
    line = pieces[root]
    if len(line) < 3 or len(pieces) < 2:
        return None
    sizes = np.fromiter(map(len, pieces), dtype=np.intp, count=len(pieces))
    beside, along, offset = _signed_offsets(line, np.concatenate(pieces), reach)
    which = np.repeat(np.arange(len(pieces)), sizes)
    judged = np.flatnonzero(np.bincount(which[beside], minlength=len(pieces)) >= samples)
    if len(judged) < 2:
        return None
    keep = beside & np.isin(which, judged)
    which, offset = which[keep], offset[keep]
    stretch = (along[keep] / step).astype(np.intp)
    middle = np.array([np.median(offset[which == k]) for k in judged])
    rank = np.full(len(pieces), -1)
    rank[judged[np.argsort(middle, kind="stable")]] = np.arange(len(judged))
    longest = np.array([arc_lengths(pieces[k])[-1] for k in judged])  # for each judged
    n = int(stretch.max()) + 1
    best = None
    for cut in range(len(judged) - 1):
        low_side = rank[which] <= cut
        (lo0, middle0, hi0), (lo1, middle1, hi1) = (
            _bin_stats(stretch[side], offset[side], n)[1:] for side in (low_side, ~low_side))
        both = np.isfinite(hi0) & np.isfinite(lo1)
        shorter = min(longest[rank[judged] <= cut].max(), longest[rank[judged] > cut].max())
        if both.sum() < max(2, share * shorter / step):  # drawn on, not beside each other
            continue
        if not np.all(middle1[both] > middle0[both]):  # they cross: one loose line
            continue
        band = float(np.percentile((lo1 - hi0)[both], 25))
        spread = float(np.median(np.maximum(hi0 - lo0, hi1 - lo1)[both]))
        if (best is None or band > best[0]) and clear(
                band, spread, (judged[rank[judged] <= cut], judged[rank[judged] > cut])):
            best = (band, cut)
    if best is None:
        return None
    low = set(judged[rank[judged] <= best[1]].tolist())
    side = low if root in low else set(judged.tolist()) - low
    first = [k for k in range(len(pieces)) if k in side or k not in judged]
    return first, [k for k in range(len(pieces)) if k not in first]


def fitted_centreline(pieces: list[np.ndarray], work: Work) -> tuple[np.ndarray, bool]:
    """:func:`centreline` of ``pieces`` at the work's width and tuning (passes 4 and 8)."""
    t = work.tuning
    return centreline(pieces, t.member_reach * work.d, work.h, t.bin * work.d,
                      t.smooth * work.d, end_zone=t.end_zone, loop_length=t.loop_length,
                      corner=t.cut_angle, corner_reach=t.cut_reach * work.d,
                      round_share=t.round_share)


class GroupFit(NamedTuple):
    """What :func:`fit_group` finds of one set of pieces before it fits any part of it
    again: the parts a band or parting passes split them into (``sides``, indices into the
    set; :func:`band_split`, :func:`parted`), or their line and which of them it keeps
    (``keep``; None for a single piece). The band and the line are a function of the
    pieces and the result's params alone, so a slider's replays share them
    (:class:`core.curves.memo.StrokeMemo`); the parts, of the pass-3 pairs among them too
    (each pair's parting kept in the memo)."""

    sides: tuple[list[int], ...] | None  #: the two sides of a band, the parts, or None
    line: np.ndarray | None  #: the fitted centreline (None where they are split)
    closed: bool  #: whether the line is a ring
    keep: np.ndarray | None  #: (pieces,) which pieces the line keeps as members


def group_fit(members: list[int], work: Work) -> GroupFit:
    """The :class:`GroupFit` of ``members``: a band's sides, else the parts where two of
    them part (:func:`parted`), else their line; what depends on the pieces alone from
    the work's memo where it has it."""
    store = getattr(work.memo, "groups", None)
    key = (work.merged, tuple(members))  # at epsilon 0 the pieces are the whole strokes
    got = store.get(key) if store is not None else None
    if got is None:
        got = _band_or_line(members, work, line=False, known=None)
        if store is not None:
            store.put(key, got)
    if got.sides is not None:
        return got
    # the pass-3 pairs among them differ from one epsilon to the next
    split = parted(members, _pairs_among(members, work.pairs), work)
    if split is not None:
        return GroupFit(split, None, False, None)
    if got.line is None:
        got = _band_or_line(members, work, line=True, known=got)
        if store is not None:
            store.put(key, got)
    return got


def _band_or_line(members: list[int], work: Work, line: bool, known: GroupFit | None
                  ) -> GroupFit:
    """What of :class:`GroupFit` depends on the pieces alone: the sides of a band that
    parts them, else, where ``line`` is asked for, their line and the members it keeps
    (else none yet). ``known``: what was found before without the line."""
    t = work.tuning
    reach = t.member_reach * work.d
    pieces = [work.pieces[k] for k in members]
    sides = None
    if known is None and len(members) > 1:
        ink = np.concatenate(pieces)  # the group's ink, asked about at every cut

        def parts(band: float, spread: float, cut: tuple[np.ndarray, np.ndarray]) -> bool:
            bundles = min(len(cut[0]), len(cut[1])) >= 2
            return clear_band(band, spread, work) and not one_loose_line(
                band, spread, bundles, ink, members, work)

        sides = band_split(pieces, reach, work.d, parts, t.along_share, t.band_samples)
    if sides is not None:
        return GroupFit(sides, None, False, None)
    if not line:
        return GroupFit(None, None, False, None)
    fitted, closed = fitted_centreline(pieces, work)
    fitted.flags.writeable = False  # shared by every replay that asks for it
    keep = None
    if len(members) > 1:
        share, leaves = runs_along(fitted, pieces, reach, t.crumb * work.d, closed)
        keep = (share >= t.member_share) & ~leaves
        keep.flags.writeable = False
    return GroupFit(None, fitted, closed, keep)


def fit_group(members: list[int], work: Work) -> list[Line]:
    """The lines of one group of pieces (see the module): split at a band that parts
    them, or fitted as one line, the pieces that do not lie along it split off and
    fitted again among themselves."""
    got = group_fit(members, work)
    if got.sides is not None:
        return [line for side in got.sides
                for line in fit_group([members[k] for k in side], work)]
    keep = got.keep
    if keep is None or keep.all() or not keep.any():
        return [Line(got.line, got.closed, tuple(members))]
    kept = [m for m, ok in zip(members, keep) if ok]
    out = fit_group(kept, work)
    return out + [line for rest in components([m for m, ok in zip(members, keep) if not ok],
                                                work.pairs)
                  for line in fit_group(rest, work)]


def _pairs_among(members: list[int], pairs: np.ndarray | None) -> np.ndarray:
    """The ``pairs`` whose two pieces are both ``members``, as indices into ``members``,
    in their order."""
    if pairs is None or len(members) < 2:
        return np.zeros((0, 2), dtype=np.intp)
    index = {m: k for k, m in enumerate(members)}
    inside = np.isin(pairs, members).all(axis=1)
    return np.vectorize(index.get, otypes=[np.intp])(pairs[inside]) if inside.any() else \
        np.zeros((0, 2), dtype=np.intp)


def _labelled(members: list[int], labels) -> list[list[int]]:
    out: dict[int, list[int]] = {}
    for m, label in zip(members, labels):
        out.setdefault(label, []).append(m)
    return list(out.values())


def components(members: list[int], pairs: np.ndarray | None) -> list[list[int]]:
    """``members`` split into the connected components of the ``pairs`` among them."""
    if pairs is None or len(members) < 2:
        return [[m] for m in members]
    return _labelled(members, component_labels(len(members), _pairs_among(members, pairs)
                                               ).tolist())


def parted(members: list[int], local: np.ndarray, work: Work
           ) -> tuple[list[int], ...] | None:
    """``members`` (indices of pieces) split where two of them run along each other and
    then part, each going on (:func:`core.lines.along.parting`, of the pass-3 pairs among
    them, ``local``, as indices into ``members``, those sharing most first), as indices
    into ``members``: the components of those pairs joined pair by pair, a pair skipped
    where it would put two parting pieces in one part (a short pass along both would
    chain them). None where no two part."""
    if not len(local):
        return None
    apart = _parting_of(np.asarray(members, dtype=np.intp)[local], work)
    if not apart.any():
        return None
    parts = _labelled(list(range(len(members))),
                      kept_apart_labels(len(members), local, apart).tolist())
    return tuple(parts) if len(parts) > 1 else None


def _parting_of(pairs: np.ndarray, work: Work) -> np.ndarray:
    """Whether the two pieces of each of ``pairs`` (indices of pieces) part, from the
    work's memo where it has it (a function of the two pieces alone). Two passes of one
    line lie within a loose pass's reach of its middle, either side of it: they part only
    farther than twice ``member_reach`` apart."""
    store = getattr(work.memo, "parting", None)
    out = np.zeros(len(pairs), bool)
    todo = []
    for k, (a, b) in enumerate(pairs.tolist()):
        got = store.get((work.merged, a, b)) if store is not None else None
        if got is None:
            todo.append(k)
        else:
            out[k] = got
    if todo:
        asked = pairs[todo]
        used, local = np.unique(asked, return_inverse=True)
        t = work.tuning
        found = parting([work.pieces[g] for g in used.tolist()], local.reshape(-1, 2),
                        2 * t.member_reach * work.d, t.crumb * work.d)
        out[todo] = found
        if store is not None:
            for (a, b), got in zip(asked.tolist(), found.tolist()):
                store.put((work.merged, a, b), got)
    return out


def along_pairs(lines: list[Line], work: Work, asked: np.ndarray | None = None
                ) -> np.ndarray:
    """Pairs (shorter, longer) of lines of which the shorter lies along the longer: at
    least ``tuning.along_share`` of its points within d_eps of it, running within
    ``tuning.along_cos`` of its direction (pass 5). Of two as long, the smaller index is
    the shorter. ``asked``: (k, 2) the pairs (either way round) to answer for, each a
    function of its two lines alone (default: every pair); only the asked shorter lines'
    points are measured, and only against the asked longer lines.

    >>> from core.lines.work import Line
    >>> x = np.linspace(0, 10, 21)[:, None]
    >>> line = lambda y, n=21: Line(np.hstack([x[:n], 0 * x[:n] + y]), False, ())
    >>> w = Work(None, None, Tuning(), 1.0, 0.5, [])
    >>> lines = [line(0.0), line(0.5, 11), line(5.0, 11)]
    >>> along_pairs(lines, w).tolist(), along_pairs(lines, w, np.array([[0, 2]])).tolist()
    ([[1, 0]], [])
    """
    if len(lines) < 2:
        return np.zeros((0, 2), dtype=np.intp)
    n = len(lines)
    lengths = np.array([ln.length for ln in lines])
    if asked is None:
        shorter = longer = np.arange(n)
        wanted = None
    else:
        a, b = asked[:, 0], asked[:, 1]
        swap = (lengths[a] > lengths[b]) | ((lengths[a] == lengths[b]) & (a > b))
        short, long_ = np.where(swap, b, a), np.where(swap, a, b)
        shorter, longer = np.unique(short), np.unique(long_)
        wanted = short.astype(np.int64) * n + long_
    pts = [lines[k].points for k in shorter.tolist()]
    segs = Segments.of([lines[k].points for k in longer.tolist()])
    sizes = np.fromiter(map(len, pts), dtype=np.intp, count=len(pts))
    which = np.repeat(shorter, sizes)
    points = np.concatenate(pts)
    tan = np.concatenate([tangents(lines[k].points, lines[k].closed)
                          for k in shorter.tolist()])
    i, seg = segs.running_along(points, tan, work.d, work.tuning.along_cos)
    other = longer[segs.polyline[seg]]
    ok = ((other != which[i])
          & ((lengths[other] > lengths[which[i]])
             | ((lengths[other] == lengths[which[i]]) & (other > which[i]))))
    i, other = i[ok], other[ok]
    key = np.unique(i.astype(np.int64) * n + other)  # each sample and line once
    line_of, partner = which[key // n], key % n
    pair_key = line_of.astype(np.int64) * n + partner
    uniq, count = np.unique(pair_key, return_counts=True)
    if wanted is not None:
        asked_for = np.isin(uniq, wanted)
        uniq, count = uniq[asked_for], count[asked_for]
    share = count / np.bincount(which, minlength=n)[uniq // n]
    good = share >= work.tuning.along_share
    return np.stack([uniq[good] // n, uniq[good] % n], axis=1)


def absorb_lines(lines: list[Line], work: Work, band=None) -> list[Line]:
    """``lines`` without those lying wholly within ``tuning.absorb_reach`` d_eps of a
    longer line: shorter than ``tuning.crumb`` d_eps (a hook, a scrap), or, where ``band``
    (a test of two line indices) allows, of any length (a loose pass the fit split off);
    either only where the longer line stands for it as a join's line must
    (:func:`_joint_fits`: in place, or apart from the other lines), else a short line
    drawn close beside a long one is lost. Their pieces become that line's members (the
    one most of their points lie near), its geometry unchanged."""
    t = work.tuning
    lengths = np.array([ln.length for ln in lines])
    if len(lines) < 2:
        return lines
    crumbs = lengths < t.crumb * work.d
    asked = [k for k in sorted(range(len(lines)), key=lambda k: (lengths[k], k))
             if band is not None or crumbs[k]]
    if not asked:
        return lines
    segs = Segments.of([ln.points for ln in lines])  # a tree of single segments: a
    owner: dict[int, int] = {}  # long line's points are not each walked along a long line
    # the lines within reach of each point of every line asked about, in one query
    sizes = np.array([len(lines[k].points) for k in asked])
    point, seg = segs.tree.query(shapely.points(np.concatenate([lines[k].points
                                                                 for k in asked])),
                                 predicate="dwithin", distance=t.absorb_reach * work.d)
    order = np.argsort(point, kind="stable")
    point, seg = point[order], seg[order]
    firsts = np.cumsum(sizes) - sizes
    of = np.searchsorted(firsts, point, side="right") - 1  # which asked line
    rows = np.split(np.stack([point - firsts[of], segs.polyline[seg]]),
                    np.searchsorted(of, np.arange(1, len(asked))), axis=1)
    for k, (i, j) in zip(asked, rows):
        crumb = bool(crumbs[k])
        pts = lines[k].points
        ij = np.unique(i.astype(np.int64) * len(lines) + j)
        i, j = ij // len(lines), ij % len(lines)
        keep = (lengths[j] > lengths[k]) & (j != k)
        i, j = i[keep], j[keep]
        others, count = np.unique(j, return_counts=True)
        # the absorbing line: near every point, most points first; never one absorbed
        for o in others[np.argsort(-count, kind="stable")].tolist():
            near_all = len(np.unique(i[j == o])) == len(pts)
            if o in owner or not (near_all or (crumb and len(np.unique(i)) == len(pts))):
                continue
            if (crumb or band(k, o)) and _joint_fits([lines[k]], [lines[o]], segs, [k, o],
                                                     work):
                owner[k] = o
            break
    if not owner:
        return lines
    extra: dict[int, list[int]] = {}
    for k, o in owner.items():
        while o in owner:  # absorbed into a line absorbed in turn
            o = owner[o]
        extra.setdefault(o, []).extend(lines[k].members)
    return [Line(ln.points, ln.closed, tuple(sorted(ln.members + tuple(extra.get(k, ())))),
                 ln.meets) for k, ln in enumerate(lines) if k not in owner]


def regroup(lines: list[Line], pairs: np.ndarray, work: Work,
            fits: dict[tuple[int, ...], list[Line]] | None = None) -> list[Line]:
    """``lines`` with each connected set of ``pairs`` fitted again as one group, where the
    joint fit validates it (:func:`_joint_fits`); else, for a set of three lines or more,
    each of its pairs judged so on its own (a chain of pairs may join two lines drawn
    twice each: each pair is one line, the chain is not); else they stay as they were.
    ``fits``: joint fits by their pieces, kept by a caller that regroups round after
    round (a group's fit depends on its pieces and ``work`` alone; a chain refused in one
    round comes back in the next)."""
    if not len(pairs):
        return lines
    fits = {} if fits is None else fits
    joined = component_labels(len(lines), pairs).tolist()
    merged: dict[int, list[int]] = {}
    for k, label in enumerate(joined):
        merged.setdefault(label, []).append(k)
    every = Segments.of([ln.points for ln in lines])
    out = []
    for same in merged.values():
        if len(same) == 1:
            out.append(lines[same[0]])
            continue
        joint = _fitted(sorted(m for k in same for m in lines[k].members), work, fits)
        if _joint_fits([lines[k] for k in same], joint, every, same, work):
            out += joint
        elif len(same) == 2:
            out += [lines[k] for k in same]
        else:  # a chain of pairs that is not one line: its pairs, each on its own
            inside = pairs[np.isin(pairs, same).all(axis=1)]
            out += _pairwise(lines, inside, every, work, fits)
    return out


def _fitted(members: list[int], work: Work, fits: dict[tuple[int, ...], list[Line]]
            ) -> list[Line]:
    """:func:`fit_group` of ``members``, once for each set of them in ``fits``."""
    key = tuple(members)
    if key not in fits:
        fits[key] = fit_group(members, work)
    return fits[key]


def _pairwise(lines: list[Line], pairs: np.ndarray, every: Segments, work: Work,
              fits: dict[tuple[int, ...], list[Line]]) -> list[Line]:
    """The lines of ``pairs`` (indices into ``lines``), each pair whose joint fit
    validates it joined, in the order of the pairs (each line joined once; a later round
    of pass 5 may join the joint lines on)."""
    done: set[int] = set()
    out = []
    for a, b in pairs.tolist():
        if a in done or b in done:
            continue
        joint = _fitted(sorted(lines[a].members + lines[b].members), work, fits)
        if _joint_fits([lines[a], lines[b]], joint, every, [a, b], work):
            out += joint
            done.update((a, b))
    return out + [lines[k] for k in sorted(set(pairs.ravel().tolist()) - done)]


def _joint_fits(before: list[Line], joint: list[Line], every: Segments, own: list[int],
                work: Work) -> bool:
    """Whether the lines ``before`` (indices ``own`` among ``every``'s polylines) are one
    line, by their joint fit ``joint``: it keeps each of them in place (the distance
    within which ``tuning.join_share`` of each lies, their *move*, at most
    ``tuning.join_reach`` d_eps), or it lies apart from every other line (along at least
    half of it, none within ``tuning.apart`` times the largest move): two lines drawn
    close among others would both move to a line between them; passes of one loose line
    drawn in open paper are one line, however far apart."""
    t = work.tuning
    moves = work.store("moves")
    key = (tuple(ln.members for ln in before), tuple(ln.members for ln in joint))
    move = moves.get(key)
    if move is None:
        segs = Segments.of([ln.points for ln in joint])
        move = max(float(np.quantile(segs.distance(ln.points), t.join_share))
                   for ln in before)
        moves[key] = move
    if move <= t.join_reach * work.d:
        return True
    reach = t.apart * move  # asked every half reach along it (its points lie h apart)
    return lies_apart(np.concatenate([ln.points for ln in joint])[::max(1, int(reach / (
        2 * work.h)))], own, reach, every, t.apart_share)


def run(work: Work) -> Work:
    labels = work.labels if work.labels is not None else np.arange(len(work.pieces))
    groups: dict[int, list[int]] = {}
    for k, label in enumerate(labels.tolist()):
        groups.setdefault(label, []).append(k)
    return work.with_(lines=[line for members in groups.values()
                             for line in fit_group(members, work)])
