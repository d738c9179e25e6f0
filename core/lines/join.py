"""Pass 5 of :mod:`core.lines`: two lines that fit one curve are joined, by the paper's own
test. The agglomeration judged the complex's pieces, cut at every crossing; a pass along
part of a long line pairs with the short piece it lies beside, and merged into that piece
it changes its shape by more than epsilon, where merged into the whole line it barely
changes it. So whole fitted lines are judged again as the merge loop judges two free
curves (3.2.2): paired side by side, overlapping, or end to end across a gap under d_eps
(:func:`core.merge.curve_merge.pair_and_merge_many`), and joined where the merged
curve's Fourier descriptor distance to either line is below epsilon, or where one
carries on from the other (overlapping at an end, or end to end): the Fourier distance
sees a longer arc as a change of shape, and five arcs of a circle never joined; or where
the two close one loop between them, each carrying on from each end of the other (a ring
drawn as two arcs: the curve merge pairs one end only, :func:`_close_each_other`); or end
to end where the merge's blend of the two is no curve (an arc turning over 90 degrees past
the other's end), but only round a loop, the other joined pairs linking them anyway
(:func:`_round_a_loop`: three arcs of a circle; an open chain, a spiral's turns, is the
merge's to pair); and where the shorter lies along the longer (within d_eps, running within
``tuning.along_cos``, 15 degrees, of its direction: a fitted line's course) over
``tuning.along_share`` of its length (:func:`core.lines.fit.along_pairs`: a loose pass
the Fourier distance sees as a change of shape). Either way, only where the two inks
leave no band free of ink wider than ``params.fill_gap`` between them
(:func:`one_band`): the residual width of the joint line is small against the distance
between the two, or they are two lines drawn close. Joined lines are
fitted again as one group from all their ink (pass 4's check splits off again a piece
that does not lie along the joint line), and stay joined only where that fit keeps each
of them in place, ``tuning.join_share`` of it within ``tuning.join_reach`` d_eps of the
joint line (:func:`core.lines.fit.regroup`): that is the fit validating the group, as
StrokeStrip's joint parameterization does; two lines drawn close would both move onto a
line between them, and a line joined on round a corner would be pulled off its ink. A
chain of pairs whose joint fit fails is judged pair by pair, each line joined once a
round. For up to ``tuning.join_rounds`` rounds (fewer where one joins nothing). Not at epsilon 0.

Invariant: every pair is judged on the lines alone, all pairs of a round at once: the
result does not depend on any order of judging.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import shapely

from ..arrays.components import component_labels
from ..arrays.geometry import project_on
from ..merge.curve_merge import SampledCurve, continues, pair_and_merge_many, sample_spacing
from ..merge.fourier import curve_descriptors, fd_distance
from .fit import along_pairs, one_loose_line, regroup
from .work import Line, Work

__all__ = ["Judged", "half_width", "joined_pairs", "one_band", "run"]


class Judged(NamedTuple):
    """What pass 5 finds of two lines, whatever the epsilon: a function of the two lines
    alone (each the fit of its pieces), so kept by their pieces from round to round and
    from replay to replay (:class:`core.curves.memo.StrokeMemo`)."""

    #: how the curve-curve merge pairs them ('side', 'overlap', 'end'), or, where it does
    #: not, whether they close a loop between them ('ring') or go on end to end where its
    #: blend is no curve ('round')
    how: str | None
    cost: float  #: a side-by-side merge's Fourier distance to the nearer line (else inf)
    along: bool  #: the shorter lies along the longer (:func:`core.lines.fit.along_pairs`)


def _judge(lines: list[Line], a: np.ndarray, b: np.ndarray, work: Work) -> list[Judged]:
    """:class:`Judged` of each pair ``(a[k], b[k])`` of lines (``a < b``), all at once."""
    d, params = work.d, work.params
    used = np.unique(np.concatenate([a, b]))
    row = np.zeros(len(lines), dtype=np.intp)
    row[used] = np.arange(len(used))
    sub = [lines[k] for k in used.tolist()]
    curves = SampledCurve.many([ln.points for ln in sub], sample_spacing(d))
    weight = [float(len(ln.members)) for ln in sub]
    ra, rb = row[a].tolist(), row[b].tolist()
    found = pair_and_merge_many([(curves[i], weight[i], curves[j], weight[j])
                                 for i, j in zip(ra, rb)], d, params.angle)
    cost = np.full(len(a), np.inf)
    paired = [k for k, (how, m) in enumerate(found) if m is not None and how == "side"]
    if paired:
        ends = np.unique(np.concatenate([a[paired], b[paired]]))
        fds = curve_descriptors([found[k][1] for k in paired]
                                + [lines[k].points for k in ends.tolist()], params.samples)
        merged, own = fds[:len(paired)], fds[len(paired):]
        at = {int(k): r for r, k in enumerate(ends.tolist())}
        for k, m in zip(paired, merged):
            cost[k] = min(float(fd_distance(own[at[int(a[k])]], m)),
                          float(fd_distance(own[at[int(b[k])]], m)))
    along = {(int(x), int(y)) for x, y in
             along_pairs(sub, work, np.stack([row[a], row[b]], axis=1)).tolist()}
    lengths = np.array([ln.length for ln in sub])
    how = [h if m is not None else None for h, m in found]
    cos_max = math.cos(math.radians(params.angle))
    open_ = [k for k, h in enumerate(how) if h is None]
    if open_:
        rings = _close_each_other([(curves[ra[k]], curves[rb[k]]) for k in open_], d, cos_max)
        for k in np.asarray(open_)[rings].tolist():
            how[k] = "ring"
    for k in [k for k, h in enumerate(how) if h is None]:
        # end to end, where the merge loop's blend of the two is no curve (an arc turning
        # over 90 degrees beyond the other's end): joined only round a loop (see
        # :func:`joined_pairs`)
        if continues(curves[ra[k]], curves[rb[k]], d, cos_max):
            how[k] = "round"
    return [Judged(h, float(c), ((i, j) if lengths[i] <= lengths[j] else (j, i)) in along)
            for h, c, i, j in zip(how, cost.tolist(), ra, rb)]


def _close_each_other(pairs: list[tuple[SampledCurve, SampledCurve]], d: float,
                      cos_max: float) -> np.ndarray:
    """Whether each pair of open curves closes one loop: each end of each lies within
    ``d`` of the other, and one carries on from each end of the other, heading the way it
    was going there (a ring drawn as two arcs, overlapping or meeting at both ends): what
    the curve-curve merge, which pairs one carrying on from one end of the other only,
    leaves as two open lines overlapping at both ends."""
    if not pairs:
        return np.zeros(0, dtype=bool)
    n = len(pairs)

    def ends_near(ends_of: int) -> np.ndarray:
        """Whether both ends of each pair's curve ``ends_of`` lie within d of the other."""
        rows = np.array([pair[ends_of].ends for pair in pairs])  # point, tangent, point, ...
        other = np.array([pair[1 - ends_of].line for pair in pairs], dtype=object)
        tips = shapely.points(np.concatenate([rows[:, 0:2], rows[:, 4:6]]))
        return (shapely.distance(tips, np.tile(other, 2)) <= d).reshape(2, n).all(axis=0)

    near = ends_near(0) & ends_near(1)
    out = np.zeros(n, dtype=bool)
    for k in np.flatnonzero(near).tolist():
        a, b = pairs[k]
        # where b's start and end lie along a, and a's direction there
        s = shapely.line_locate_point(a.line, shapely.points(b.points[[0, -1]]))
        at = np.clip(np.searchsorted(a.s, s), 0, len(a.s) - 1)
        t0, t1 = b.tangents[0] @ a.tangents[at[0]], b.tangents[-1] @ a.tangents[at[1]]
        if t0 < 0:  # walk b the other way round
            t0, t1, s = -t1, -t0, s[::-1]
        # b leaves from near a's end, heading on, and comes back in at a's start
        out[k] = bool(t0 >= cos_max and t1 >= cos_max and s[0] > s[1])
    return out


def joined_pairs(lines: list[Line], work: Work, known=None) -> np.ndarray:
    """The pairs of lines pass 5 judges one line at ``work.params.epsilon`` (see the
    module), before the band test: first those the curve-curve merge joins, or that close
    a loop (smaller index first), then those of which the shorter lies along the longer
    (shorter first).
    ``known``: :class:`Judged` by the two lines' pieces (a dict, or the memo's store)."""
    if len(lines) < 2:
        return np.zeros((0, 2), dtype=np.intp)
    known = {} if known is None else known
    geoms = np.array([shapely.LineString(ln.points) for ln in lines], dtype=object)
    a, b = shapely.STRtree(geoms).query(geoms, predicate="dwithin", distance=work.d)
    keep = a < b
    a, b = a[keep], b[keep]
    keys = [(lines[i].members, lines[j].members) for i, j in zip(a.tolist(), b.tolist())]
    got = [known.get(key) for key in keys]
    todo = np.array([k for k, g in enumerate(got) if g is None], dtype=np.intp)
    if len(todo):
        for k, judged in zip(todo.tolist(), _judge(lines, a[todo], b[todo], work)):
            got[k] = judged
            known[keys[k]] = judged
    eps = work.params.epsilon
    # carried on from one another (overlapping at an end, or end to end across a gap
    # under d_eps): one motion of the line drawn on, whatever the change of shape
    joins = np.array([g.how is not None and (g.how != "side" or g.cost < eps) for g in got],
                     dtype=bool)
    how = np.array([g.how for g in got], dtype=object)
    joins &= _round_a_loop(len(lines), a, b, joins & (how != "side"), how == "round")
    along = np.array([g.along for g in got], dtype=bool)
    lengths = np.array([ln.length for ln in lines])
    swap = lengths[a] > lengths[b]  # shorter first; of two as long, the smaller index
    short, long_ = np.where(swap, b, a)[along], np.where(swap, a, b)[along]
    order = np.argsort(short.astype(np.int64) * len(lines) + long_, kind="stable")
    return np.concatenate([np.stack([a[joins], b[joins]], axis=1),
                           np.stack([short[order], long_[order]], axis=1)]).astype(np.intp)


def _round_a_loop(n: int, a: np.ndarray, b: np.ndarray, carried: np.ndarray,
                  ends: np.ndarray) -> np.ndarray:
    """Of the pairs (``a[k]``, ``b[k]``) of ``n`` lines, the ``ends`` ones (end to end
    where the merge loop's blend is no curve) are kept only where the other ``carried``
    pairs (joined, each carrying on from the other: not side by side) link their two
    lines anyway: arcs drawn one after another round a loop. An open chain of such arcs (a
    spiral's turns) is left to the merge loop's own pairing. Other pairs are kept.

    >>> a, b = np.array([0, 1, 0]), np.array([1, 2, 2])  # three arcs round a loop
    >>> _round_a_loop(3, a, b, np.ones(3, bool), np.ones(3, bool)).tolist()
    [True, True, True]
    >>> _round_a_loop(3, a[:2], b[:2], np.ones(2, bool), np.ones(2, bool)).tolist()
    [False, False]
    >>> _round_a_loop(2, a[:0], b[:0], np.ones(0, bool), np.ones(0, bool)).tolist()
    []
    """
    keep = np.ones(len(a), dtype=bool)
    for k in np.flatnonzero(carried & ends).tolist():
        others = carried.copy()
        others[k] = False
        label = component_labels(n, np.stack([a[others], b[others]], axis=1))
        keep[k] = bool(label[a[k]] == label[b[k]])
    return keep


def half_width(line: Line, work: Work, known) -> float:
    """How far a line's own ink spreads from it: the ``tuning.spread_percentile`` of its
    pieces'
    distances to it (0 for a single clean pass). ``known``: widths by pieces (a dict, or
    the memo's store), filled here; in passes 5 and 6 a line is the fit of its pieces, so
    the pieces say which line it is."""
    width = known.get(line.members)
    if width is None:
        ink = np.concatenate([work.pieces[m] for m in line.members])
        width = float(np.percentile(project_on(line.points, ink).distance,
                                    work.tuning.spread_percentile))
        known[line.members] = width
    return width


def one_band(lines: list[Line], pairs: np.ndarray, work: Work,
             known: dict[tuple[int, ...], float] | None = None,
             gaps: dict | None = None) -> np.ndarray:
    """The pairs whose inks leave no band free of ink wider than ``params.fill_gap`` (the
    drawing's own spacing of passes within a bundle) between them, or are one loose line
    whatever the band (:func:`core.lines.fit.one_loose_line`: not two tight bundles, and
    no other ink near but that of the lines the pairs join them to): the gap between the
    lines (the median distance from the shorter's points beside the longer to it) less
    the half-widths of both inks (:func:`half_width`). Two tight bundles drawn close keep
    a clear band; the passes of one loose line fill it, or stand alone. ``known``: the
    half-widths by pieces, kept by a caller that asks about many pairs of the same lines;
    ``gaps``: the gaps by the two lines' pieces, likewise."""
    if not len(pairs):
        return pairs
    known = {} if known is None else known
    gaps = {} if gaps is None else gaps
    chain = component_labels(len(lines), pairs)
    pieces_of: dict[int, list[int]] = {}  # each chain's pieces, once, where asked
    keep = np.zeros(len(pairs), bool)
    for k, (a, b) in enumerate(pairs.tolist()):
        short, long_ = (a, b) if lines[a].length <= lines[b].length else (b, a)
        key = (lines[short].members, lines[long_].members)
        gap = gaps.get(key)
        if gap is None:
            dist = project_on(lines[long_].points, lines[short].points).distance
            beside = dist[dist <= work.d]
            gap = float(np.median(beside)) if len(beside) else float(dist.min())
            gaps[key] = gap
        widths = half_width(lines[a], work, known), half_width(lines[b], work, known)
        band = gap - sum(widths)
        if band <= work.params.fill_gap:
            keep[k] = True
            continue
        if chain[a] not in pieces_of:
            pieces_of[chain[a]] = [m for j in np.flatnonzero(chain == chain[a]).tolist()
                                   for m in lines[j].members]
        bundles = min(len(lines[a].members), len(lines[b].members)) >= 2
        keep[k] = one_loose_line(band, 2 * max(widths), bundles,
                                 np.concatenate([lines[a].points, lines[b].points]),
                                 pieces_of[chain[a]], work)
    return pairs[keep]


def run(work: Work) -> Work:
    lines = work.current_lines()
    if not work.merged:
        return work.with_(lines=lines)
    # within this pass every line is its pieces' fit (pass 4's, or a join's): fits and
    # widths are kept by pieces from round to round
    fits: dict = {}
    widths, gaps, judged = work.store("widths"), work.store("gaps"), work.store("judged")
    for _ in range(work.tuning.join_rounds):
        pairs = one_band(lines, joined_pairs(lines, work, judged), work, widths, gaps)
        if not len(pairs):
            break
        joined = regroup(lines, pairs, work, fits)
        if not {id(ln) for ln in joined} - {id(ln) for ln in lines}:
            break  # no new line: the next round would judge the same lines again
        lines = joined
    return work.with_(lines=lines)
