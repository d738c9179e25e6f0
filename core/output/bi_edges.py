"""The bi-edge pass (paper 3.3): edges that still run side by side after agglomeration (the
two long sides of a slender border patch, or a free curve along an outline) are merged by
the curve-curve operator again, while a merge costs less than epsilon.

Candidate pairs (boxes within d_eps; not two free curves, which agglomeration has judged,
except in the pass over whole strokes, ``every_pair``, which it never saw as such; with
most of five points of the shorter edge within d_eps of the longer, or an end of it: the
edges that overlap, one carried on past the other's end) are swept closest first, by the
mean distance of those points. Each candidate stands for whatever its edges have been
merged into by then; a pair already merged into one is skipped, and every pair of current
edges is judged once: paired and merged by :func:`pair_and_merge_many`, costed as
min(d(A, M), d(B, M)), and merged if it pairs (side by side or overlapping; joins end to
end are the stroke graph's) and costs less than epsilon. Taking the overlaps too took
doubled ink 0.117 -> 0.112 and strokes per intended curve 1.069 -> 1.045 on the 101 dev
sketches (medians; tight recall unchanged). Costed lazily this way, a dense cluster of k
overlapping edges costs about k merges, not the k * k pairs among them.

:func:`merge_filled_bundles` runs the pass over whole strokes once more with d_eps widened
to ``FILL_REACH`` d_eps, on the pairs whose space between the ink fills (:class:`InkFill`):
a bundle drawn a little wider than d_eps leaves two lines along its sides with strokes
between them, where two lines drawn close leave an empty band.

Invariant: the result depends on the edges and parameters alone (and the ink, for
:func:`merge_filled_bundles`). Judgments are made in batches (the pair needed and the next
few), found in the memo from other runs or not; each is exact whatever batch it was made
in (:mod:`core.arrays.polylines`), and the memo keys them by d_eps too.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from itertools import islice

import numpy as np
import shapely

from ..arrays.geometry import directions_at, lines_from, nearest_on, unit_rows
from ..curves.memo import StrokeMemo
from ..merge.curve_merge import SampledCurve, pair_and_merge_many, sample_spacing
from ..merge.fourier import curve_descriptors, fd_distance
from ..params import SimplifyParams
from .stroke_graph import Edge

__all__ = ["FILL_REACH", "JUDGE_AHEAD", "BiEdgePass", "InkFill", "merge_bi_edges",
           "merge_filled_bundles"]

#: pairs of edges judged in one batch: the one needed and up to this many of the candidates
#: coming next (the later ones are wasted when a merge before them changes their edges)
JUDGE_AHEAD = 32

#: candidates settled by earlier merges are dropped this many at a time with array
#: operations (a dense drawing has millions of candidates, most of them settled)
CANDIDATE_BLOCK = 4096

#: how far apart, in d_eps, lines may lie and still be one bundle when ink fills the space
#: between them (:func:`merge_filled_bundles`). The doubled lines this merges on the dev
#: cartoons lie 0.9 to 1.1 d_eps apart; at 2.5 d_eps product sketches lost close
#: construction lines (tight recall 0.814 -> 0.808) for no more cartoons merged
FILL_REACH = 1.6

#: the cross-sections of a pair, at these fractions along the shorter line
FILL_SECTIONS = (0.25, 0.5, 0.75)

#: ink counts as running along a pair where it crosses a cross-section at least this far
#: from square (|cos| of the angle to the section at most this: within 30 degrees of the
#: pair's direction); a stroke across the pair is no part of its bundle
ALONG_COS = 0.5


def merge_bi_edges(edges: list[Edge], params: SimplifyParams, memo: StrokeMemo,
                   every_pair: bool = False) -> list[Edge]:
    """The edges after the bi-edge pass (see the module docstring). ``every_pair``: pairs
    of two free edges are candidates too (whole strokes, which the merge loop never saw
    as such)."""
    return BiEdgePass(edges, params, memo, every_pair).run()


def merge_filled_bundles(strokes: list[Edge], params: SimplifyParams, memo: StrokeMemo,
                         fill: InkFill | None) -> list[Edge]:
    """Whole strokes after merging those that lie side by side up to :data:`FILL_REACH`
    d_eps apart where the ink (``fill``: the base curves, and ``params.fill_gap``) fills
    the space between them.

    A bundle drawn a little wider than d_eps leaves two output lines along its sides, each
    the middle of the strokes nearer to it. Whether they are one bundle or two lines drawn
    close is in the ink between them: strokes running along the pair that leave no band
    wider than ``params.fill_gap`` free (:class:`InkFill`) are the one bundle; an empty
    band is the space between two lines. Such pairs are judged as by the bi-edge pass,
    with d_eps widened to the reach. ``fill`` None (``fill_gap`` 0): the strokes as they
    were.
    """
    params = params.resolved()
    if fill is None or len(strokes) < 2:
        return strokes
    wide = replace(params, alpha=FILL_REACH * params.alpha)
    return BiEdgePass(strokes, wide, memo, every_pair=True, fill=fill).run()


@dataclass(eq=False)
class InkFill:
    """Whether ink fills the space between two lines (:func:`merge_filled_bundles`).

    Three cross-sections run from points of the shorter line (:data:`FILL_SECTIONS`) to
    the nearest points of the longer; where the ink running along the pair crosses a
    section (:data:`ALONG_COS`) cuts it into gaps, and a section is filled when no gap is
    wider than ``gap``. A pair is filled when at least two sections lie within the reach
    and each of those is filled.
    """

    ink: np.ndarray  #: the ink as shapely LineStrings
    gap: float  #: the widest gap a filled section may have
    tree: shapely.STRtree = field(init=False, repr=False)  #: of ``ink``, made with it

    def __post_init__(self) -> None:
        self.tree = shapely.STRtree(self.ink)

    @classmethod
    def of(cls, curves: list[np.ndarray], params: SimplifyParams) -> InkFill | None:
        """The fill of the ink ``curves`` (the base curves) with ``params.fill_gap``
        (params resolved), or None when that is 0: no space counts as filled."""
        return cls(lines_from(curves), params.fill_gap) if params.fill_gap > 0 else None

    def pairs(self, lines: np.ndarray, i: np.ndarray, j: np.ndarray,
              reach: float) -> np.ndarray:
        """For each pair of ``lines`` (i, j): whether ink fills the space between them."""
        if len(i) == 0:
            return np.zeros(0, dtype=bool)
        k = len(FILL_SECTIONS)
        length = shapely.length(lines)
        first_shorter = length[i] <= length[j]
        short, long_ = np.where(first_shorter, i, j), np.where(first_shorter, j, i)
        start = shapely.line_interpolate_point(np.repeat(lines[short], k),
                                               np.tile(FILL_SECTIONS, len(i)), normalized=True)
        a = shapely.get_coordinates(start)
        b = nearest_on(np.repeat(lines[long_], k), start)
        span = np.hypot(*(b - a).T)
        within = (span <= reach).reshape(-1, k)
        widest = self._widest_gaps(a, b, reach / 8) * span
        filled = ((widest <= self.gap).reshape(-1, k) | ~within).all(axis=1)
        return filled & (within.sum(axis=1) >= 2)

    def _widest_gaps(self, a: np.ndarray, b: np.ndarray, step: float) -> np.ndarray:
        """For each section from ``a`` to ``b``: the widest gap between the points where
        ink running along the pair crosses it (and its ends), as a fraction of its length.
        The ink's direction is taken over ``step`` each side of where it crosses."""
        n = len(a)
        sections = shapely.linestrings(np.stack([a, b], axis=1))
        sec, ink = self.tree.query(sections, predicate="intersects")
        parts, part_of = shapely.get_parts(shapely.intersection(sections[sec], self.ink[ink]),
                                           return_index=True)
        repeat = shapely.get_num_coordinates(parts)
        sec, ink = np.repeat(sec[part_of], repeat), np.repeat(ink[part_of], repeat)
        at = shapely.get_coordinates(parts)
        direction = b - a
        if len(at):  # the ink's direction where it crosses: along the pair, or across
            tangent = directions_at(self.ink[ink], shapely.points(at), step)
            across = np.abs((tangent * unit_rows(direction[sec])).sum(axis=1))
            sec, at = sec[across <= ALONG_COS], at[across <= ALONG_COS]
        t = ((at - a[sec]) * direction[sec]).sum(axis=1) / np.maximum(
            (direction[sec] ** 2).sum(axis=1), 1e-300)
        t = np.concatenate([t.clip(0, 1), np.zeros(n), np.ones(n)])
        sec = np.concatenate([sec, np.arange(n), np.arange(n)])
        order = np.lexsort((t, sec))
        t, sec = t[order], sec[order]
        same = sec[1:] == sec[:-1]
        widest = np.zeros(n)
        np.maximum.at(widest, sec[1:][same], np.diff(t)[same])
        return widest


class BiEdgePass:
    """One run of the pass over a list of edges.

    Edges are numbered: the given ones first, each merged edge appended. ``root[k]`` is
    the current edge that edge k has been merged into (k itself while it stands).
    """

    def __init__(self, edges: list[Edge], params: SimplifyParams, memo: StrokeMemo,
                 every_pair: bool = False, fill: InkFill | None = None) -> None:
        self.params = params = params.resolved()  # alpha a number
        self.every_pair = every_pair
        self.fill = fill  # when given: only pairs whose space between ink fills
        self.d_eps = params.alpha
        self.memo = memo
        self.input = edges
        self.points: list[np.ndarray] = [e.points for e in edges]
        self.weights: list[float] = [1.0] * len(edges)  # how many edges each stands for
        self.free: list[bool] = [e.free for e in edges]
        self.perimeter: list[float] = [e.perimeter for e in edges]  # merged: inf
        self.root = np.arange(2 * len(edges))  # room for every merge there can be
        # keys (a * len(root) + b) of pairs of current edges judged, in the order judged
        self.judged: dict[int, None] = {}
        # this run's samples, descriptors and judgments by edge number (from the memo or
        # made here; the memo may let go of them, this run may not)
        self._curves: dict[int, SampledCurve] = {}
        self._fds: dict[int, np.ndarray] = {}
        self._pairs: dict[tuple[int, int], tuple[np.ndarray, np.ndarray] | None] = {}

    # -- what is known of edges and pairs ------------------------------------------------------
    def _memo_key(self, a: int, b: int) -> tuple:
        return (self.points[a].tobytes(), self.weights[a], self.points[b].tobytes(),
                self.weights[b], self.d_eps)

    def _judged_before(self, pair: tuple[int, int]) -> bool:
        """Whether the pair's judgment is at hand (this run's, or the memo's)."""
        if pair in self._pairs:
            return True
        key = self._memo_key(*pair)
        if key in self.memo.pairs:
            self._pairs[pair] = self.memo.pairs.get(key)
            return True
        return False

    def _sample(self, edges: list[int]) -> None:
        """Sample the edges not sampled yet, together."""
        todo: dict[tuple[bytes, float], list[int]] = {}
        for k in edges:
            if k not in self._curves:
                key = (self.points[k].tobytes(), self.d_eps)  # sampled at d_eps / 2
                if key in self.memo.curves:
                    self._curves[k] = self.memo.curves.get(key)
                else:
                    todo.setdefault(key, []).append(k)
        made = SampledCurve.many([self.points[ks[0]] for ks in todo.values()],
                                 sample_spacing(self.d_eps))
        for (key, ks), curve in zip(todo.items(), made):
            self.memo.curves.put(key, curve)
            self._curves.update(dict.fromkeys(ks, curve))

    def _fd(self, k: int) -> np.ndarray:
        if k not in self._fds:
            key = self.points[k].tobytes()
            fd = self.memo.descriptors.get(key)
            if fd is None:
                fd = curve_descriptors([self.points[k]], self.params.samples)[0]
                self.memo.descriptors.put(key, fd)
            self._fds[k] = fd
        return self._fds[k]

    def _judge(self, pairs: list[tuple[int, int]]) -> None:
        """Pair and merge these pairs of edges at once, and describe the merged edges and
        the edges of those that pair (to be costed) in one batch."""
        self._sample([k for pair in pairs for k in pair])
        found = pair_and_merge_many(
            [(self._curves[a], self.weights[a], self._curves[b], self.weights[b])
             for a, b in pairs], self.d_eps, self.params.angle, end_to_end=False)
        merged = [m for _, m in found if m is not None]
        parts = list(dict.fromkeys(
            k for (a, b), (_, m) in zip(pairs, found) if m is not None for k in (a, b)
            if k not in self._fds and self.points[k].tobytes() not in self.memo.descriptors))
        fds = curve_descriptors(merged + [self.points[k] for k in parts], self.params.samples)
        for k, row in zip(parts, fds[len(merged):]):
            self._fds[k] = row.copy()
            self.memo.descriptors.put(self.points[k].tobytes(), self._fds[k])
        rows = iter(fds)
        for (a, b), (_, m) in zip(pairs, found):
            self._pairs[(a, b)] = None if m is None else (m, next(rows).copy())
            self.memo.pairs.put(self._memo_key(a, b), self._pairs[(a, b)])

    # -- the sweep -----------------------------------------------------------------------------
    def _current(self, u: int, v: int) -> tuple[int, int] | None:
        """The pair of current edges candidate (u, v) stands for, smaller first; None when
        they have been merged into one or that pair was judged already."""
        root = self.root  # called for every candidate: a few hundred thousand times
        a, b = int(root[u]), int(root[v])
        if a > b:
            a, b = b, a
        return (a, b) if a != b and a * len(root) + b not in self.judged else None

    def _unsettled(self, x: np.ndarray, y: np.ndarray, done: np.ndarray
                   ) -> tuple[list[int], list[int]]:
        """The candidates of a block whose edges are not merged into one and whose pair
        was not judged by the start of the block (``done``: judged keys, sorted)."""
        a, b = self.root[x], self.root[y]
        keys = np.minimum(a, b).astype(np.int64) * len(self.root) + np.maximum(a, b)
        keep = a != b
        if len(done):
            keep &= done[np.searchsorted(done, keys).clip(max=len(done) - 1)] != keys
        return x[keep].tolist(), y[keep].tolist()

    def _settle(self, pair: tuple[int, int], next_x: list[int], next_y: list[int]) -> None:
        """Judge a pair (with the candidates coming next, when not judged before) and merge
        it if it pairs and costs less than epsilon."""
        a, b = pair
        self.judged[a * len(self.root) + b] = None  # a merge replaces both: never again
        if not self._judged_before(pair):
            upcoming = dict.fromkeys(filter(None, (self._current(u, v)
                                                   for u, v in zip(next_x, next_y))))
            self._judge([pair] + [p for p in upcoming if not self._judged_before(p)])
        judgment = self._pairs[pair]
        if judgment is None:
            return
        merged, new_fd = judgment
        if min(fd_distance(self._fd(a), new_fd),
               fd_distance(self._fd(b), new_fd)) >= self.params.epsilon:
            return
        n = len(self.points)
        self.points.append(merged)
        self._fds[n] = new_fd
        if merged.tobytes() not in self.memo.descriptors:
            self.memo.descriptors.put(merged.tobytes(), new_fd)
        self.weights.append(self.weights[a] + self.weights[b])
        self.free.append(False)
        self.perimeter.append(np.inf)
        self.root[(self.root == a) | (self.root == b)] = n

    def _candidates(self) -> tuple[np.ndarray, np.ndarray]:
        """The candidate pairs (first, second edge), closest first."""
        lines = lines_from(self.points)
        # pairs whose boxes come within d_eps: the probes below keep only pairs running
        # side by side, which are within d_eps, so GEOS need not measure every distance
        lo = shapely.bounds(lines)
        d = self.d_eps
        i, j = shapely.STRtree(lines).query(shapely.box(*(lo[:, :2] - d).T,
                                                        *(lo[:, 2:] + d).T))
        free = np.array(self.free)
        keep = (i < j) if self.every_pair else (i < j) & ~(free[i] & free[j])
        i, j = i[keep], j[keep]
        if len(i) == 0:
            return i, j
        closeness, beside = _beside(lines, i, j, d)
        if self.fill is not None:
            beside[beside] = self.fill.pairs(lines, i[beside], j[beside], d)
        order = np.lexsort((j, i, closeness))
        order = order[beside[order]]
        return i[order], j[order]

    def run(self) -> list[Edge]:
        if len(self.points) < 2:
            return self.input
        first, second = self._candidates()
        if len(first) == 0:
            return self.input
        done = np.empty(0, dtype=np.int64)  # judged keys, sorted, as of the last block
        for start in range(0, len(first), CANDIDATE_BLOCK):
            if len(self.judged) > len(done):
                done = np.union1d(done, np.fromiter(islice(self.judged, len(done), None),
                                                      np.int64))
            xs, ys = self._unsettled(first[start:start + CANDIDATE_BLOCK],
                                     second[start:start + CANDIDATE_BLOCK], done)
            for k, (u, v) in enumerate(zip(xs, ys)):
                pair = self._current(u, v)
                if pair is not None:
                    self._settle(pair, xs[k + 1:k + 1 + JUDGE_AHEAD],
                                 ys[k + 1:k + 1 + JUDGE_AHEAD])
        return [Edge(self.points[k], self.perimeter[k], self.free[k])
                for k in range(len(self.points)) if self.root[k] == k]


def _beside(lines: np.ndarray, i: np.ndarray, j: np.ndarray, d_eps: float,
            chunk: int = 50_000) -> tuple[np.ndarray, np.ndarray]:
    """For each pair (i, j): the mean distance of five points along the shorter line to the
    longer, and whether at least two of them lie within d_eps (it runs along it).

    The five points of each line are made once; pairs are measured in chunks, as a dense
    drawing has millions of them."""
    length = shapely.length(lines)
    probes = shapely.line_interpolate_point(np.repeat(lines, 5),
                                            np.tile(np.linspace(0, 1, 5), len(lines)),
                                            normalized=True).reshape(-1, 5)
    closeness, beside = np.empty(len(i)), np.empty(len(i), dtype=bool)
    for k in range(0, len(i), chunk):
        a, b = i[k:k + chunk], j[k:k + chunk]
        first_shorter = length[a] <= length[b]
        short, long_ = np.where(first_shorter, a, b), np.where(first_shorter, b, a)
        dist = shapely.distance(probes[short], lines[long_][:, None])
        closeness[k:k + chunk] = dist.mean(axis=1)
        near = dist <= d_eps
        # along it, or an end beside it (an overlap, where one carries on past the other)
        beside[k:k + chunk] = (near.mean(axis=1) >= 0.4) | near[:, 0] | near[:, 4]
    return closeness, beside
