"""The merge loop's own rules: the queue's order, stale entries re-costed, compaction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core import build_base_complex
from core.complex.complex_state import MergeKind
from core.merge.agglomeration import Agglomerator
from core.merge.queue import COMPACT_MIN, MergeQueue, QueueEntry
from core.params import SimplifyParams

PP, CP, CC = MergeKind.PP, MergeKind.CP, MergeKind.CC


def test_at_equal_cost_curves_go_into_patches_then_curves_merge_then_patches():
    queue = MergeQueue()
    for kind, a in ((PP, 1), (CC, 2), (PP, 3), (CP, 4), (CC, 5), (CP, 6)):
        queue.push(0.0, kind, a, a + 100, True)
    queue.push(-1.0, PP, 7, 107, True)  # cheaper wins whatever its kind
    popped = [(e.kind, e.a) for e in (queue.pop() for _ in range(7))]
    # within a kind, in the order pushed
    assert popped == [(PP, 7), (CP, 4), (CP, 6), (CC, 2), (CC, 5), (PP, 1), (PP, 3)]


def test_a_pair_that_may_not_merge_is_not_queued():
    queue = MergeQueue()
    queue.push(math.inf, PP, 0, 1, True)
    assert len(queue) == 0


def test_looking_ahead_leaves_the_pop_order_as_it_was():
    rng = np.random.default_rng(0)
    costs = rng.choice([0.0, 0.1, 0.2], 300)
    kinds = rng.choice(list(MergeKind), 300)

    def filled() -> MergeQueue:
        queue = MergeQueue()
        for k, (cost, kind) in enumerate(zip(costs, kinds)):
            queue.push(float(cost), MergeKind(kind), k, k + 1, bool(k % 2))
        return queue

    plain, looked = filled(), filled()
    ahead = looked.next_entries(64)
    assert len(looked) == 300
    order = [plain.pop() for _ in range(300)]
    assert ahead == order[:64]
    assert [looked.pop() for _ in range(300)] == order


def test_compaction_drops_dead_entries_only_and_keeps_the_order():
    queue = MergeQueue()
    n = 2 * COMPACT_MIN + 10
    for k in range(n):
        queue.push(float(k % 7), PP, k, k + 1, True)
    dead = set(range(0, n, 3))
    reference = MergeQueue()
    for k in range(n):
        reference.push(float(k % 7), PP, k, k + 1, True)
    assert queue.compact(lambda e: e.a not in dead)
    assert len(queue) == n - len(dead)
    expected = [e for e in (reference.pop() for _ in range(n)) if e.a not in dead]
    assert [queue.pop() for _ in range(len(expected))] == expected


def test_a_small_queue_is_not_compacted():
    queue = MergeQueue()
    for k in range(2 * COMPACT_MIN):
        queue.push(1.0, CC, k, k + 1, True)
    assert not queue.compact(lambda e: False)
    assert len(queue) == 2 * COMPACT_MIN


def doubled_grid() -> list[np.ndarray]:
    """Three horizontal and three vertical lines, each drawn twice 0.4% apart: thin slivers
    and small squares between the passes, which may merge (the grid's big faces may not)."""
    t = np.linspace(-0.05, 1.05, 30)
    lines = []
    for k in (0.2, 0.5, 0.8):
        for off in (0.0, 0.004):
            lines.append(np.stack([t, np.full_like(t, k + off)], axis=1))
            lines.append(np.stack([np.full_like(t, k + off), t], axis=1))
    return lines


@pytest.fixture()
def agglomerator() -> Agglomerator:
    """The doubled grid's complex, its pairs queued (nothing merged yet)."""
    agg = Agglomerator(build_base_complex(doubled_grid()), SimplifyParams().resolved())
    agg._initial_pairs()
    return agg


def first_of(agg: Agglomerator, kind: MergeKind) -> QueueEntry:
    return next(e for e in agg.queue.next_entries(len(agg.queue)) if e.kind == kind)


def test_a_stale_entry_reaching_the_top_is_costed_and_queued_again_fresh(agglomerator):
    agg = agglomerator
    pair = first_of(agg, PP)
    assert pair.fresh and 0 < pair.cost < agg.params.epsilon
    # the same pair queued stale under a lower estimate, alone in the queue
    agg.queue = MergeQueue()
    agg.queue.push(pair.cost / 10, PP, pair.a, pair.b, False)
    assert agg.step()
    assert agg.history == [] and agg.stats.stale_recosts == 1
    entry = agg.queue.pop()
    assert (entry.kind, entry.a, entry.b, entry.fresh) == (PP, pair.a, pair.b, True)
    assert entry.cost == pair.cost  # a cost depends on its pair alone


def test_a_fresh_entry_below_epsilon_merges_and_offers_the_new_patch_stale(agglomerator):
    agg = agglomerator
    pair = first_of(agg, PP)
    rest = [e for e in agg.queue.next_entries(len(agg.queue)) if e != pair]
    agg.queue = MergeQueue()
    agg.queue.push(pair.cost, PP, pair.a, pair.b, True)
    for e in rest:  # the others after it
        agg.queue.push(e.cost + 1.0, e.kind, e.a, e.b, e.fresh)
    assert agg.step()
    (merge,) = agg.history
    assert (merge.kind, merge.first, merge.second, merge.cost) == (PP, pair.a, pair.b,
                                                                     pair.cost)
    new = merge.result
    assert not agg.state.patch_alive[pair.a] and agg.state.patch_alive[new]
    offered = [e for e in agg.queue.next_entries(len(agg.queue)) if new in (e.a, e.b)]
    assert offered and not any(e.fresh for e in offered)  # estimates from the parents


def test_entries_of_merged_away_primitives_are_skipped(agglomerator):
    agg = agglomerator
    pair = first_of(agg, PP)
    agg.queue = MergeQueue()
    agg.queue.push(pair.cost, PP, pair.a, pair.b, True)
    agg.step()
    agg.queue.push(0.0, PP, pair.a, pair.b, True)  # both gone now
    assert agg.step()  # skipped, and the run goes on
    assert len(agg.history) == 1


def test_the_first_fresh_cost_not_below_epsilon_ends_the_run():
    agg = Agglomerator(build_base_complex(doubled_grid()), SimplifyParams(epsilon=0.0).resolved())
    agg._initial_pairs()
    assert len(agg.queue) > 0
    assert not agg.step()
    assert agg.history == []
