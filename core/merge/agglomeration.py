"""Agglomeration (paper 3.2): greedily merge the pair of primitives whose merge changes
shape least, until the cheapest change exceeds epsilon.

Three kinds of pair, each costed with the Fourier descriptor distance d:

* PP, two patches sharing a curve: w = min(d(P, P u Q), d(Q, P u Q));
* CP, a free curve touching a patch at a node: w = d(P, P u C), with P u C the patch's
  outline with the curve walked out and back where it touches (the paper's O_p u O_l);
  the curve is then merged away into the patch's outline;
* CC, two free curves side by side or end to end (:mod:`core.curve_merge`):
  w = min(d(A, M), d(B, M)) with M the merged curve.

Beyond the paper, a merge must not move ink far: whatever it removes (the curves between
two patches, a free curve, the two curves a merged one replaces) must lie within d_eps =
alpha * D of what stays. The Fourier distance is blind to scale, so without this guard tiny
faces would merge across real lines and erase them.

The queue holds (cost, rank, order, kind, a, b, fresh) entries: at equal cost (exact ties
are common: absorbing a sliver of no area costs 0) free curves go into patches first, then
curves merge, then patches, as a patch merge makes a new patch whose pairs all come up
again. Merged primitives get new ids, so an entry whose primitive has gone is skipped.
When a patch grows or two curves merge, the pairs they had are pushed again for the new
primitive, keyed by their parents' cheapest known cost but marked stale (none if every
parent pair was invalid, costed at once if no parent pair was ever costed); a stale entry
reaching the top is re-costed and pushed back, and only fresh costs are merged or end the
run. The run is deterministic and eps-independent up to its stop (the first fresh cost not below
epsilon: so epsilon = 0 merges nothing), and the history of one run with epsilon replays,
cut at the first cost not below epsilon2, exactly to the run with epsilon2.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field

import numpy as np
import shapely

from ..arrays.geometry import lines_from
from ..complex.base_complex import BaseComplex
from ..complex.complex_state import ComplexState, Merge
from ..complex.patch_rings import (
    Outline,
    RingGeometry,
    half_edges,
    spike_walk,
    union_outline_points,
    union_rings,
)
from ..params import SimplifyParams
from .curve_merge import SampledCurve, pair_and_merge_many, sample_spacing
from .fourier import curve_descriptors, fd_distance, fourier_descriptors
from .guard import DistanceGuard, PatchCurves

INF = math.inf
#: stale pairs with a patch (patch-patch, curve-patch) are keyed by this fraction of the
#: estimate their parents' costs give
PP_ESTIMATE = 0.7
#: at equal cost, the kind of merge made first
TIE_RANK = {"CP": 0, "CC": 1, "PP": 2}
#: shapes described together when the queue is first filled (a batch of 256 rings takes
#: about 1 MB of samples)
COST_BATCH = 256
#: queue entries looked at, when a stale curve-curve pair comes up, for the stale such
#: pairs to cost with it in one batch (the ones next in line are the likeliest to be
#: wanted before a merge removes one of their curves)
LOOK_AHEAD = 64


@dataclass
class AgglomerationStats:
    pairs_costed: dict[str, int] = field(default_factory=lambda: {"PP": 0, "CP": 0, "CC": 0})
    merges: dict[str, int] = field(default_factory=lambda: {"PP": 0, "CP": 0, "CC": 0})
    stale_recosts: int = 0


class Agglomerator:
    """Runs the agglomeration on a base complex (unit-diagonal frame)."""

    def __init__(self, cx: BaseComplex, params: SimplifyParams) -> None:
        self.params = params
        self.d_eps = params.alpha  # D = 1 in the unit frame
        self.state = ComplexState(cx)
        self.geometry = RingGeometry(cx)
        self.lines = lines_from(cx.curves) if cx.curves else np.empty(0, dtype=object)
        self.guard = DistanceGuard(cx.curves, self.lines, self.d_eps, cx.curve_nodes,
                                   cx.node_curves)
        self.outlines: dict[int, Outline] = {}
        self.rings: list[list[list[int]]] = [
            [half_edges(p.boundary)] + [half_edges(h) for h in p.holes] for p in cx.patches]
        self.patch_fd: dict[int, np.ndarray] = {}
        self.curve_fd: dict[int, np.ndarray] = {}
        self.sampled: dict[int, SampledCurve] = {}
        self.known: dict[tuple, float] = {}
        self.precosted: dict[tuple[int, int], float] = {}  # curve-curve costs worked out ahead
        # curves that curve-curve pairs cheaper than epsilon would merge into, kept from
        # their costing for when they are applied (not their descriptors: a dense sketch
        # has tens of thousands of such pairs, and a descriptor is the bigger of the two)
        self.merged: dict[tuple[int, int], np.ndarray] = {}
        self.cp_partners: dict[int, set[int]] = {}
        self.cc_partners: dict[int, set[int]] = {}
        self.heap: list[tuple] = []
        self._compacted_size = COST_BATCH
        self.order = 0
        self.history: list[Merge] = []
        self.stats = AgglomerationStats()

    # -- descriptors -----------------------------------------------------------------------
    def _fds(self, rings: list[np.ndarray]) -> np.ndarray:
        return fourier_descriptors(rings, self.params.samples)

    def _patch_fd(self, p: int) -> np.ndarray:
        if p not in self.patch_fd:
            self.patch_fd[p] = self._fds([self.geometry.points(self.rings[p][0])])[0]
        return self.patch_fd[p]

    def _sampled(self, c: int) -> SampledCurve:
        if c not in self.sampled:
            self._sample([c])
        return self.sampled[c]

    def _sample(self, curves: list[int]) -> None:
        """Sample the curves not sampled yet, together. A base curve takes the samples the
        guard made of it alike; a merged curve is resampled."""
        missing = sorted({c for c in curves if c not in self.sampled})
        base = [c for c in missing if c < len(self.guard.samples)]
        new = [c for c in missing if c >= len(self.guard.samples)]
        self.sampled.update(zip(base, SampledCurve.many([self.guard.samples[c] for c in base])))
        self.sampled.update(zip(new, SampledCurve.many([self.state.curves[c] for c in new],
                                                       sample_spacing(self.d_eps))))

    def _curve_fd(self, c: int) -> np.ndarray:
        if c not in self.curve_fd:
            self._describe_curves([c])
        return self.curve_fd[c]

    def _describe_curves(self, curves: list[int]) -> None:
        """Describe the curves not yet described, in one batch (rows copied out of it, so
        that a curve merged away frees its own row only)."""
        missing = sorted({c for c in curves if c not in self.curve_fd})
        if missing:
            fds = curve_descriptors([self.state.curves[c] for c in missing], self.params.samples)
            self.curve_fd.update((c, row.copy()) for c, row in zip(missing, fds))

    def _size(self, p: int) -> float:
        """Linear size of a patch: the square root of its outer ring's area."""
        return math.sqrt(max(self.geometry.area(self.rings[p][0]), 0.0))

    # -- costs -------------------------------------------------------------------------------
    def _outline(self, p: int) -> Outline:
        if p not in self.outlines:
            self.outlines[p] = Outline(self.rings[p][0], self.geometry)
        return self.outlines[p]

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
        points = union_outline_points(self._outline(p), self._outline(q), shared)
        if points is None:
            rings = union_rings(self.rings[p], self.rings[q], shared, self.geometry)
            if not rings:
                return None
            points = self.geometry.points(rings[0])
        x, y = points[:, 0], points[:, 1]
        if x[:-1] @ y[1:] - x[1:] @ y[:-1] + x[-1] * y[0] - x[0] * y[-1] <= 0:
            return None  # not a face: the union turned inside out
        return points

    def _cp_outline(self, c: int, p: int) -> np.ndarray | None:
        """P's outer ring with curve C walked out and back where it touches, or None."""
        st = self.state
        if c < len(self.guard.samples):
            covered = self.guard.covered([c], st.patch_curves[p])
        else:  # a curve made by a curve-curve merge: measured, not tabled
            covered = self.guard.covered([], st.patch_curves[p], self._sampled(c).points)
        if not covered:
            return None
        ends = {int(n) for e in st.patch_curves[p] for n in self.geometry.curve_nodes[e]}
        nodes = sorted(st.curve_nodes[c] & ends)
        if not nodes:
            return None
        anchor = st.base.nodes[nodes[0]]
        return self.geometry.with_spike(self.rings[p][0], nodes[0],
                                        spike_walk(st.curves[c], anchor))

    def _cc_curves(self, pairs: list[tuple[int, int]]) -> list[np.ndarray | None]:
        """The curve that would replace each pair A, B, or None when they do not pair."""
        st = self.state
        self._sample([c for pair in pairs for c in pair])
        found = pair_and_merge_many(
            [(self._sampled(a), st.curve_weight[a], self._sampled(b), st.curve_weight[b])
             for a, b in pairs], self.d_eps, self.params.angle)
        return [merged for _, merged in found]

    def _costs(self, kind: str, pairs: list[tuple[int, int]]) -> list[float]:
        """Costs of many pairs of one kind, their new shapes described in one batch.

        PP: min(d(P, P u Q), d(Q, P u Q)); CP: d(P, P u C); CC: min(d(A, M), d(B, M)).
        """
        self.stats.pairs_costed[kind] += len(pairs)
        if kind == "CC":
            shapes = self._cc_curves(pairs)
        else:
            make = self._pp_outline if kind == "PP" else self._cp_outline
            shapes = [make(a, b) for a, b in pairs]
        valid = [i for i, shape in enumerate(shapes) if shape is not None]
        costs = [INF] * len(pairs)
        if valid:
            describe = curve_descriptors if kind == "CC" else fourier_descriptors
            new = describe([shapes[i] for i in valid], self.params.samples)
            ref = self._curve_fd if kind == "CC" else self._patch_fd
            if kind == "CC":
                self._describe_curves([c for i in valid for c in pairs[i]])
            first = np.stack([ref(pairs[i][0 if kind != "CP" else 1]) for i in valid])
            dist = fd_distance(first, new)
            if kind != "CP":
                dist = np.minimum(dist, fd_distance(
                    np.stack([ref(pairs[i][1]) for i in valid]), new))
            for i, d in zip(valid, dist.tolist()):
                costs[i] = d
                if kind == "CC" and d < self.params.epsilon:
                    self.merged[pairs[i]] = shapes[i]
        return costs

    def _cost(self, kind: str, a: int, b: int) -> float:
        """The cost of one pair, known from now on (its children are offered with it).

        A curve-curve pair is costed in one batch with the stale such pairs among the next
        ``LOOK_AHEAD`` entries of the queue (ten times cheaper a pair than one at a time);
        their costs wait in ``precosted`` until their own entries reach the top. A cost
        depends on the pair alone, so costing it early changes nothing but the work done.
        """
        if kind == "CC" and (a, b) not in self.precosted:
            batch = sorted({(a, b)} | {(x, y) for _, _, _, k, x, y, fresh in self._next_entries()
                                       if k == "CC" and not fresh and (x, y) not in self.precosted
                                       and self._alive(k, x, y)})
            self.precosted.update(zip(batch, self._costs("CC", batch)))
        cost = self.precosted.pop((a, b)) if kind == "CC" else self._costs(kind, [(a, b)])[0]
        self.known[(kind, a, b)] = cost
        return cost

    # -- the queue ---------------------------------------------------------------------------
    def _next_entries(self) -> list[tuple]:
        """The next ``LOOK_AHEAD`` entries of the queue, left in it (their keys are unique,
        so it pops in the same order after)."""
        entries = [heapq.heappop(self.heap) for _ in range(min(LOOK_AHEAD, len(self.heap)))]
        for entry in entries:
            heapq.heappush(self.heap, entry)
        return entries

    def _push(self, cost: float, kind: str, a: int, b: int, fresh: bool) -> None:
        if cost < INF:
            heapq.heappush(self.heap, (cost, TIE_RANK[kind], self.order, kind, a, b, fresh))
            self.order += 1

    def _offer(self, kind: str, a: int, b: int, parents: list[tuple],
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
        if not known or (kind == "PP" and min(known) == INF):
            # a grown patch may pass the guard where its parts did not: look again
            self._push(self._cost(kind, a, b), kind, a, b, True)
            return
        # the Fourier distance of a patch to its union with a small neighbour falls as the
        # patch grows: the estimate follows the growth in size, and is keyed lower still so
        # that pairs which became cheap surface in time. Children inherit the estimate, not
        # the key: discounting at every growth would decay a busy patch's pairs to nothing
        # and re-cost them all each time it absorbs a sliver.
        estimate = min(known)
        self.known[(kind, a, b)] = estimate
        if estimate < INF:
            self._push(estimate * (PP_ESTIMATE if kind != "CC" else 1.0), kind, a, b, False)

    def _alive(self, kind: str, a: int, b: int) -> bool:
        st = self.state
        if kind == "PP":
            return st.patch_alive[a] and st.patch_alive[b]
        if kind == "CP":
            return st.curve_alive[a] and st.patch_alive[b]
        return st.curve_alive[a] and st.curve_alive[b]

    def _pair_cp(self, c: int, p: int) -> None:
        self.cp_partners.setdefault(p, set()).add(c)

    def _initial_pairs(self) -> None:
        st = self.state
        for k in range(0, len(self.rings), COST_BATCH):  # the base patches' descriptors
            batch = self.rings[k:k + COST_BATCH]
            fds = self._fds([self.geometry.points(rings[0]) for rings in batch])
            self.patch_fd.update(zip(range(k, k + len(batch)), fds))
        pp = sorted({(min(a, b), max(a, b)) for a, b in st.curve_sides if a != b and a >= 0
                     and b >= 0})
        self._push_costed("PP", pp)
        free = [c for c in range(len(st.curves)) if st.is_free(c)]
        cp = [(c, p) for c in free
              for p in sorted({p for n in st.curve_nodes[c] for p in st.patches_at_node(n)})]
        for c, p in cp:
            self._pair_cp(c, p)
        self._push_costed("CP", cp)
        if len(free) > 1:
            lines = self.lines[free]
            i, j = shapely.STRtree(lines).query(lines, predicate="dwithin",
                                                distance=self.d_eps)
            cc = sorted({(free[x], free[y]) for x, y in zip(i.tolist(), j.tolist()) if x < y})
            for a, b in cc:
                self.cc_partners.setdefault(a, set()).add(b)
                self.cc_partners.setdefault(b, set()).add(a)
            self._push_costed("CC", cc)

    def _push_costed(self, kind: str, pairs: list[tuple[int, int]]) -> None:
        """Cost pairs in batches (of a size that keeps the samples small) and queue them."""
        for k in range(0, len(pairs), COST_BATCH):
            batch = pairs[k:k + COST_BATCH]
            for (a, b), cost in zip(batch, self._costs(kind, batch)):
                self.known[(kind, a, b)] = cost
                self._push(cost, kind, a, b, True)

    def _neighbour_patches(self, r: int) -> set[int]:
        st = self.state
        return {s for c in st.patch_curves[r] for s in st.curve_sides[c] if s >= 0 and s != r}

    def _apply(self, kind: str, a: int, b: int, cost: float) -> None:
        st = self.state
        if kind == "PP":
            rings = union_rings(self.rings[a], self.rings[b], st.shared_curves(a, b),
                                self.geometry)
            r = st.merge_patches(a, b)
            self.rings.append(rings)
            self.history.append(Merge("PP", cost, a, b, r))
            size = self._size(r)
            growth = [self._size(x) / size if size > 0 else 1.0 for x in (a, b)]
            self._forget(a)
            self._forget(b)
            for t in sorted(self._neighbour_patches(r)):
                self._offer("PP", t, r, [("PP", min(x, t), max(x, t)) for x in (a, b)], growth)
            partners = self.cp_partners.pop(a, set()) | self.cp_partners.pop(b, set())
            for c in sorted(x for x in partners if st.curve_alive[x]):
                self._pair_cp(c, r)
                self._offer("CP", c, r, [("CP", c, a), ("CP", c, b)])
        elif kind == "CP":
            st.remove_curve(a)
            self._forget_curve(a)
            self.history.append(Merge("CP", cost, a, b, b))
        else:
            merged = self.merged.pop((a, b))
            n = st.merge_curves(a, b, merged)
            self._forget_curve(a)
            self._forget_curve(b)
            self.history.append(Merge("CC", cost, a, b, n, merged))
            partners = (self.cc_partners.pop(a, set()) | self.cc_partners.pop(b, set())) - {a, b}
            self.cc_partners[n] = set()
            for c in sorted(x for x in partners if st.curve_alive[x]):
                self.cc_partners[n].add(c)
                self.cc_partners.setdefault(c, set()).add(n)
                self._offer("CC", c, n, [("CC", min(x, c), max(x, c)) for x in (a, b)])
            for p in sorted({p for node in st.curve_nodes[n] for p in st.patches_at_node(node)}):
                self._pair_cp(n, p)
                self._offer("CP", n, p, [("CP", a, p), ("CP", b, p)])
        self.stats.merges[kind] += 1

    def _forget(self, p: int) -> None:
        """Drop what was kept of a patch that merged away (its ring is read no more once
        its successor's pairs are offered, which only needs sizes computed before)."""
        self.rings[p] = []
        self.outlines.pop(p, None)
        self.patch_fd.pop(p, None)

    def _forget_curve(self, c: int) -> None:
        """Drop what was kept of a curve that merged away (its samples and their points
        as geometries are the bulk of a dense sketch's memory)."""
        self.sampled.pop(c, None)
        self.curve_fd.pop(c, None)

    def _compact(self) -> None:
        """Drop queue entries of merged-away primitives once they are most of the queue;
        the order of the rest is kept (it is fixed by their (cost, rank, order) keys)."""
        if len(self.heap) > 2 * self._compacted_size:
            self.heap = [e for e in self.heap if self._alive(*e[3:6])]
            heapq.heapify(self.heap)
            self.merged = {k: v for k, v in self.merged.items() if self._alive("CC", *k)}
            self.precosted = {k: v for k, v in self.precosted.items() if self._alive("CC", *k)}
            self._compacted_size = max(len(self.heap), COST_BATCH)

    def _target_reached(self) -> bool:
        tp, tc = self.params.target_patches, self.params.target_curves
        return ((tp is not None and self.state.num_patches <= tp)
                or (tc is not None and self.state.num_curves <= tc))

    def run(self) -> list[Merge]:
        """Merge while the cheapest fresh cost is below epsilon and no target is reached."""
        self._initial_pairs()
        eps = self.params.epsilon
        while self.heap and not self._target_reached():
            cost, _, _, kind, a, b, fresh = heapq.heappop(self.heap)
            if not self._alive(kind, a, b):
                continue
            if not fresh:
                self.stats.stale_recosts += 1
                self._push(self._cost(kind, a, b), kind, a, b, True)
                continue
            if cost >= eps:
                break
            self._apply(kind, a, b, cost)
            self._compact()
        return self.history


def agglomerate(cx: BaseComplex, params: SimplifyParams) -> tuple[list[Merge], ComplexState,
                                                                  AgglomerationStats]:
    """Run the agglomeration; returns the merge history, the final state and counters."""
    agg = Agglomerator(cx, params)
    history = agg.run()
    return history, agg.state, agg.stats
