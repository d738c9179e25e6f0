"""Agglomeration (paper 3.2): greedily merge the pair of primitives whose merge changes
shape least, until the cheapest change exceeds epsilon.

Three kinds of pair, each costed with the Fourier descriptor distance d:

* PP, two patches sharing a curve: w = min(d(P, P u Q), d(Q, P u Q));
* CP, a free curve touching a patch at a node: w = d(P, P u C), with P u C the patch's
  outline with the curve walked out and back where it touches (the paper's O_p u O_l);
  the curve is then merged away into the patch's outline;
* CC, two free curves side by side or end to end (:mod:`core.curve_merge`):
  w = min(d(A, M), d(B, M)) with M the merged curve.

Beyond the paper, a merge must not move ink far: what a patch merge removes (the curves
between two patches, a free curve) must lie within ``tuning.guard_reach`` d_eps of what stays, and
a curve-curve merge's curve within d_eps (d_eps = alpha * D) of both curves it replaces.
The Fourier distance is blind to scale, so without this guard tiny faces would merge across
real lines and erase them. A patch merge keeps one side of what it removes, not their
middle: the line stage fits one line to the ink the merges grouped, wherever the kept
side lies (:mod:`core.lines`).

The queue and its order (cost, then kind at equal cost, then push order) are
:mod:`core.merge.queue`'s. Merged primitives get new ids, so an entry whose primitive has
gone is skipped. When a patch grows or two curves merge, the pairs they had are pushed
again for the new primitive, keyed by their parents' cheapest known cost but marked stale
(none if every parent pair was invalid, costed at once if no parent pair was ever
costed); a stale entry reaching the top is re-costed and pushed back, and only fresh costs
are merged or end the run.

Invariant: the run is deterministic and eps-independent up to its stop (the first fresh
cost not below epsilon: so epsilon = 0 merges nothing), and the history of one run with
epsilon replays, cut at the first cost not below epsilon2, exactly to the run with
epsilon2. That needs every cost to depend on its pair alone, whatever batch it was costed
in (:mod:`core.arrays.polylines`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely

from ..arrays.geometry import lines_from, ring_is_counter_clockwise
from ..complex.base_complex import BaseComplex
from ..complex.complex_state import ComplexState, Merge, MergeKind
from ..complex.patch_rings import RingGeometry, spike_walk, union_outline_points, union_rings
from ..params import ResolvedParams, SimplifyParams
from .curve_merge import pair_and_merge_many
from .fourier import curve_descriptors, fd_distance, fourier_descriptors
from .guard import DistanceGuard, PatchCurves
from .queue import MergeQueue, QueueEntry
from .shapes import CurveShapes, PatchShapes

__all__ = ["AgglomerationStats", "Agglomerator", "Costed", "agglomerate"]

PP, CP, CC = MergeKind.PP, MergeKind.CP, MergeKind.CC
INF = math.inf

#: a stale pair with a patch (PP, CP) is keyed by this fraction of the estimate its
#: parents' costs give: the Fourier distance of a patch to its union with a small
#: neighbour falls as the patch grows, so keyed lower, pairs that became cheap surface in
#: time to be re-costed (0.85 and 1.0 measured: docs/decisions.md, "Where each tuned
#: number comes from")
PP_ESTIMATE = 0.7

#: pairs costed in one batch when the queue is first filled: a batch of 256 rings takes
#: about 1 MB of samples
COST_BATCH = 256

#: queue entries looked at, when a stale curve-curve pair comes up, for the stale such
#: pairs to cost with it in one batch: the ones next in line are the likeliest to be
#: wanted before a merge removes one of their curves (measured: docs/decisions.md, "Where
#: each tuned number comes from")
CC_LOOK_AHEAD = 64


@dataclass
class AgglomerationStats:
    pairs_costed: dict[MergeKind, int] = field(default_factory=lambda: dict.fromkeys(MergeKind, 0))
    merges: dict[MergeKind, int] = field(default_factory=lambda: dict.fromkeys(MergeKind, 0))
    stale_recosts: int = 0


@dataclass
class Costed:
    """Costs of a batch of pairs of one kind, and the shape each would merge into.

    ``shapes[i]`` is the union's outer ring (PP), the patch's ring with the curve walked
    out and back (CP), or the merged curve (CC); None, with an infinite cost, where the
    pair may not merge.
    """

    costs: list[float]
    shapes: list[np.ndarray | None]


class Agglomerator:
    """Runs the agglomeration on a base complex (unit-diagonal frame).

    Everything kept beside the queue is declared in ``__init__`` with who fills it and who
    empties it. None of it changes a result: each is either the state of the run or a
    value that depends only on its key (a shape's descriptor, a pair's cost), kept to be
    used again.
    """

    def __init__(self, cx: BaseComplex, params: SimplifyParams) -> None:
        params = ResolvedParams.of(params)  # alpha a number
        self.params = params
        self.d_eps = params.alpha  # D = 1 in the unit frame
        self.state = ComplexState(cx)
        self.geometry = RingGeometry(cx)
        self.lines = lines_from(cx.curves) if cx.curves else np.empty(0, dtype=object)
        self.guard = DistanceGuard(cx.curves, self.lines, self.d_eps, cx.curve_nodes,
                                   cx.node_curves, params.tuning.guard_reach * self.d_eps)
        self.queue = MergeQueue()
        self.history: list[Merge] = []
        self.stats = AgglomerationStats()
        # what is kept of each alive primitive's shape, filled on first use and dropped
        # when it merges away (:mod:`core.merge.shapes`)
        self.patches = PatchShapes(cx, self.geometry, params.samples)
        self.curves = CurveShapes(self.state, self.guard, self.d_eps, params.samples)
        # -- the state of the run, beside the queue and the complex ---------------------------
        # the free curves each patch is paired with (CP), and each free curve's curve-curve
        # partners (CC): filled by _initial_pairs and the merges, popped when a side
        # merges, so that a merged primitive offers its parents' pairs again
        self.cp_partners: dict[int, set[int]] = {}
        self.cc_partners: dict[int, set[int]] = {}
        # what each queued pair cost, or its estimate (stale): set when pushed, popped by
        # _offer when one of its primitives merges (a parent pair is asked once)
        self.known: dict[tuple[MergeKind, int, int], float] = {}
        # curve-curve costs worked out ahead of their entries (_cost_one, a batch of the
        # stale such pairs next in the queue): popped when their entry comes up; pruned of
        # dead pairs when the queue is compacted
        self.precosted: dict[tuple[int, int], float] = {}
        # the curves that curve-curve pairs cheaper than epsilon would merge into, kept
        # from their costing (_cost_batch) for _merge_curves; pruned when the queue is
        # compacted. Not their descriptors: a dense sketch has tens of thousands of such
        # pairs, and a descriptor is the bigger of the two
        self.merged: dict[tuple[int, int], np.ndarray] = {}

    # -- the new shape of a pair -----------------------------------------------------------------
    def _pp_outline(self, p: int, q: int) -> np.ndarray | None:
        """The outer ring of P u Q, or None when the pair may not merge."""
        st = self.state
        shared = st.shared_curves(p, q)
        if not shared:
            return None
        allowed = PatchCurves(st.patch_curves[p], st.patch_curves[q], shared)
        if not self.guard.covered(shared, allowed):
            return None
        # the union's outer ring, all a descriptor needs: quick when the shared curves are
        # one run on both outer rings (holes do not change it), else the general walk
        points = union_outline_points(self.patches.outline(p), self.patches.outline(q), shared)
        if points is None:
            rings = union_rings(self.patches.rings[p], self.patches.rings[q], shared,
                                 self.geometry)
            if not rings:
                return None
            points = self.geometry.points(rings[0])
        if not ring_is_counter_clockwise(points):
            return None  # not a face: the union turned inside out
        return points

    def _cp_outline(self, c: int, p: int) -> np.ndarray | None:
        """P's outer ring with curve C walked out and back where it touches, or None."""
        st = self.state
        if st.is_base_curve(c):
            covered = self.guard.covered([c], st.patch_curves[p])
        else:  # a curve made by a curve-curve merge: measured, not tabled
            covered = self.guard.covered([], st.patch_curves[p], self.curves.sampled(c).points)
        if not covered:
            return None
        ends = {int(n) for e in st.patch_curves[p] for n in self.geometry.curve_nodes[e]}
        nodes = sorted(st.curve_nodes[c] & ends)
        if not nodes:
            return None
        anchor = st.base.nodes[nodes[0]]
        return self.geometry.with_spike(self.patches.rings[p][0], nodes[0],
                                        spike_walk(st.curves[c], anchor))

    # -- costs: one function per kind -------------------------------------------------------------
    def _distances(self, shapes: list[np.ndarray | None], describe, sides) -> list[float]:
        """For each new shape, the smallest Fourier distance to the descriptors that
        ``sides`` give for its pair (one function per side, called with the shape's index);
        infinite where there is no shape. New shapes are described in one batch."""
        valid = [i for i, shape in enumerate(shapes) if shape is not None]
        costs = [INF] * len(shapes)
        if valid:
            new = describe([shapes[i] for i in valid], self.params.samples)
            dist = None
            for side in sides:
                d = fd_distance(np.stack([side(i) for i in valid]), new)
                dist = d if dist is None else np.minimum(dist, d)
            for i, d in zip(valid, dist.tolist()):
                costs[i] = d
        return costs

    def cost_pp(self, pairs: list[tuple[int, int]]) -> Costed:
        """Patch pairs P, Q: w = min(d(P, P u Q), d(Q, P u Q))."""
        shapes = [self._pp_outline(p, q) for p, q in pairs]
        return Costed(self._distances(shapes, fourier_descriptors, (
            lambda i: self.patches.fd(pairs[i][0]), lambda i: self.patches.fd(pairs[i][1]))),
            shapes)

    def cost_cp(self, pairs: list[tuple[int, int]]) -> Costed:
        """Curve-patch pairs C, P: w = d(P, P u C)."""
        shapes = [self._cp_outline(c, p) for c, p in pairs]
        return Costed(self._distances(shapes, fourier_descriptors,
                                      (lambda i: self.patches.fd(pairs[i][1]),)), shapes)

    def cost_cc(self, pairs: list[tuple[int, int]]) -> Costed:
        """Curve pairs A, B: w = min(d(A, M), d(B, M)), M the curve replacing both (none
        when they do not pair, :mod:`core.merge.curve_merge`)."""
        st = self.state
        self.curves.sample([c for pair in pairs for c in pair])
        found = pair_and_merge_many(
            [(self.curves.sampled(a), st.curve_weight[a], self.curves.sampled(b),
              st.curve_weight[b])
             for a, b in pairs], self.d_eps, self.params.angle,
            side_share=self.params.tuning.side_share)
        shapes = [merged for _, merged in found]
        self.curves.describe([c for pair, shape in zip(pairs, shapes) if shape is not None
                               for c in pair])
        return Costed(self._distances(shapes, curve_descriptors, (
            lambda i: self.curves.fd(pairs[i][0]), lambda i: self.curves.fd(pairs[i][1]))),
            shapes)

    def _cost_batch(self, kind: MergeKind, pairs: list[tuple[int, int]]) -> list[float]:
        """Costs of many pairs of one kind; keeps the merged curve of every curve pair that
        may be merged (cheaper than epsilon) for :meth:`_apply`."""
        self.stats.pairs_costed[kind] += len(pairs)
        costed = {PP: self.cost_pp, CP: self.cost_cp, CC: self.cost_cc}[kind](pairs)
        if kind == CC:
            eps = self.params.epsilon
            self.merged.update((pair, shape) for pair, shape, cost in
                               zip(pairs, costed.shapes, costed.costs) if cost < eps)
        return costed.costs

    def _cost_one(self, kind: MergeKind, a: int, b: int) -> float:
        """The cost of one pair, known from now on (its children are offered with it).

        A curve-curve pair is costed in one batch with the stale such pairs among the next
        ``CC_LOOK_AHEAD`` entries of the queue (ten times cheaper a pair than one at a
        time); their costs wait in ``precosted`` until their own entries come up. A cost
        depends on the pair alone, so costing it early changes nothing but the work done.
        """
        if kind != CC:
            cost = self._cost_batch(kind, [(a, b)])[0]
        else:
            if (a, b) not in self.precosted:
                batch = sorted({(a, b)} | {
                    (e.a, e.b) for e in self.queue.next_entries(CC_LOOK_AHEAD)
                    if e.kind == CC and not e.fresh and (e.a, e.b) not in self.precosted
                    and self._alive(e)})
                self.precosted.update(zip(batch, self._cost_batch(CC, batch)))
            cost = self.precosted.pop((a, b))
        self.known[(kind, a, b)] = cost
        return cost

    # -- pairs ---------------------------------------------------------------------------------
    def _offer(self, kind: MergeKind, a: int, b: int, parents: list[tuple],
               growth: list[float] | None = None) -> None:
        """Queue a pair of a new primitive with what its parents' pairs were worth.

        Stale under the cheapest cost a parent pair had, each scaled by ``growth`` (for a
        grown patch, how much smaller the parent was). Costed now when no parent pair was
        ever costed, or when every parent pair of two patches was refused (the grown patch
        may pass the guard); left out when every parent pair of a curve was refused.
        """
        growth = growth or [1.0] * len(parents)
        # a parent pair is asked once, when one of its primitives merges: then let it go
        known = [self.known.pop(key) * g for key, g in zip(parents, growth)
                 if key in self.known]
        if not known or (kind == PP and min(known) == INF):
            # a grown patch may pass the guard where its parts did not: look again
            self.queue.push(self._cost_one(kind, a, b), kind, a, b, True)
            return
        # the estimate follows the growth in size (PP_ESTIMATE says why it is keyed lower).
        # Children inherit the estimate, not the key: discounting at every growth would
        # decay a busy patch's pairs to nothing and re-cost them all each time it absorbs a
        # sliver.
        estimate = min(known)
        self.known[(kind, a, b)] = estimate
        if estimate < INF:
            self.queue.push(estimate * (PP_ESTIMATE if kind != CC else 1.0), kind, a, b, False)

    def _alive(self, entry: QueueEntry) -> bool:
        """Whether both primitives of a queued pair are still there."""
        st = self.state
        if entry.kind == PP:
            return st.patch_alive[entry.a] and st.patch_alive[entry.b]
        if entry.kind == CP:
            return st.curve_alive[entry.a] and st.patch_alive[entry.b]
        return st.curve_alive[entry.a] and st.curve_alive[entry.b]

    def _pair_cp(self, c: int, p: int) -> None:
        self.cp_partners.setdefault(p, set()).add(c)

    def _initial_pairs(self) -> None:
        st = self.state
        self.patches.describe_all(COST_BATCH)  # the base patches
        pp = sorted({(min(a, b), max(a, b)) for a, b in st.curve_sides if a != b and a >= 0
                     and b >= 0})
        self._push_costed(PP, pp)
        free = [c for c in range(len(st.curves)) if st.is_free(c)]
        cp = [(c, p) for c in free
              for p in sorted({p for n in st.curve_nodes[c] for p in st.patches_at_node(n)})]
        for c, p in cp:
            self._pair_cp(c, p)
        self._push_costed(CP, cp)
        if len(free) > 1:
            lines = self.lines[free]
            i, j = shapely.STRtree(lines).query(lines, predicate="dwithin",
                                                distance=self.d_eps)
            cc = sorted({(free[x], free[y]) for x, y in zip(i.tolist(), j.tolist()) if x < y})
            for a, b in cc:
                self.cc_partners.setdefault(a, set()).add(b)
                self.cc_partners.setdefault(b, set()).add(a)
            self._push_costed(CC, cc)

    def _push_costed(self, kind: MergeKind, pairs: list[tuple[int, int]]) -> None:
        """Cost pairs in batches (of a size that keeps the samples small) and queue them."""
        for k in range(0, len(pairs), COST_BATCH):
            batch = pairs[k:k + COST_BATCH]
            for (a, b), cost in zip(batch, self._cost_batch(kind, batch)):
                self.known[(kind, a, b)] = cost
                self.queue.push(cost, kind, a, b, True)

    def _neighbour_patches(self, r: int) -> set[int]:
        st = self.state
        return {s for c in st.patch_curves[r] for s in st.curve_sides[c] if s >= 0 and s != r}

    # -- merging -----------------------------------------------------------------------------
    def _apply(self, kind: MergeKind, a: int, b: int, cost: float) -> None:
        {PP: self._merge_patches, CP: self._absorb_curve, CC: self._merge_curves}[kind](
            a, b, cost)
        self.stats.merges[kind] += 1

    def _merge_patches(self, a: int, b: int, cost: float) -> None:
        st = self.state
        rings = union_rings(self.patches.rings[a], self.patches.rings[b],
                            st.shared_curves(a, b), self.geometry)
        r = st.merge_patches(a, b)
        self.patches.add(r, rings)
        self.history.append(Merge(PP, cost, a, b, r))
        size = self.patches.size(r)
        growth = [self.patches.size(x) / size if size > 0 else 1.0 for x in (a, b)]
        self.patches.forget(a)
        self.patches.forget(b)
        for t in sorted(self._neighbour_patches(r)):
            self._offer(PP, t, r, [(PP, min(x, t), max(x, t)) for x in (a, b)], growth)
        partners = self.cp_partners.pop(a, set()) | self.cp_partners.pop(b, set())
        for c in sorted(x for x in partners if st.curve_alive[x]):
            self._pair_cp(c, r)
            self._offer(CP, c, r, [(CP, c, a), (CP, c, b)])

    def _absorb_curve(self, c: int, p: int, cost: float) -> None:
        self.state.remove_curve(c)
        self.curves.forget(c)
        self.history.append(Merge(CP, cost, c, p, p))

    def _merge_curves(self, a: int, b: int, cost: float) -> None:
        st = self.state
        merged = self.merged.pop((a, b))
        n = st.merge_curves(a, b, merged)
        self.curves.forget(a)
        self.curves.forget(b)
        self.history.append(Merge(CC, cost, a, b, n, merged))
        partners = (self.cc_partners.pop(a, set()) | self.cc_partners.pop(b, set())) - {a, b}
        self.cc_partners[n] = set()
        for c in sorted(x for x in partners if st.curve_alive[x]):
            self.cc_partners[n].add(c)
            self.cc_partners.setdefault(c, set()).add(n)
            self._offer(CC, c, n, [(CC, min(x, c), max(x, c)) for x in (a, b)])
        for p in sorted({p for node in st.curve_nodes[n] for p in st.patches_at_node(node)}):
            self._pair_cp(n, p)
            self._offer(CP, n, p, [(CP, a, p), (CP, b, p)])

    def _compact(self) -> None:
        """Drop queue entries of merged-away primitives once they are most of the queue,
        and the curve pairs kept for them."""
        if self.queue.compact(self._alive):
            alive = self.state.curve_alive
            self.merged = {k: v for k, v in self.merged.items() if alive[k[0]] and alive[k[1]]}
            self.precosted = {k: v for k, v in self.precosted.items()
                              if alive[k[0]] and alive[k[1]]}

    def step(self) -> bool:
        """Take the next entry off the queue and act on it: skip it (a primitive has
        gone), re-cost it and queue it again (stale), or merge it (fresh and cheaper than
        epsilon). Returns False when the run is over."""
        if not self.queue or self.state.targets_reached(self.params.target_patches,
                                                        self.params.target_curves):
            return False
        entry = self.queue.pop()
        if not self._alive(entry):
            return True
        kind, a, b = entry.kind, entry.a, entry.b
        if not entry.fresh:
            self.stats.stale_recosts += 1
            self.queue.push(self._cost_one(kind, a, b), kind, a, b, True)
            return True
        if entry.cost >= self.params.epsilon:
            return False
        self._apply(kind, a, b, entry.cost)
        self._compact()
        return True

    def run(self) -> list[Merge]:
        """Merge while the cheapest fresh cost is below epsilon and no target is reached."""
        self._initial_pairs()
        while self.step():
            pass
        return self.history


def agglomerate(cx: BaseComplex, params: SimplifyParams) -> tuple[list[Merge], ComplexState,
                                                                  AgglomerationStats]:
    """Run the agglomeration; returns the merge history, the final state and counters."""
    agg = Agglomerator(cx, params)
    history = agg.run()
    return history, agg.state, agg.stats
