"""The agglomeration's queue of candidate merges (paper 3.2.3), with its order rules.

Entries are ordered by (cost, tie rank, push order):

* cost: the Fourier distance the merge would make (fresh), or an estimate from the pairs
  the entry's primitives had before they merged (stale, see :mod:`core.merge.agglomeration`);
* tie rank, by kind: exact ties are common (absorbing a sliver of no area costs 0); free
  curves go into patches first, then curves merge, then patches, because a patch merge
  makes a new patch whose pairs all come up again;
* push order: unique, so no two entries ever compare past it, and the run is
  deterministic.

Merged primitives get new ids, so an entry whose primitive has gone is simply skipped when
popped (lazy deletion); :meth:`MergeQueue.compact` drops such entries in bulk once they are
most of the queue, keeping the order of the rest.

Invariant: popping gives the same sequence whatever was looked at ahead
(:meth:`MergeQueue.next_entries`) or compacted, since every key is unique.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from typing import NamedTuple

from ..complex.complex_state import MergeKind

__all__ = ["COMPACT_MIN", "TIE_RANK", "MergeQueue", "QueueEntry"]

#: at equal cost, the kind of merge made first (lower first; see the module docstring)
TIE_RANK = {MergeKind.CP: 0, MergeKind.CC: 1, MergeKind.PP: 2}

#: the queue is compacted once it holds twice the entries it held after the last
#: compaction, and never below twice this size (small queues are not worth the pass)
COMPACT_MIN = 256


class QueueEntry(NamedTuple):
    """One candidate merge: a frozen record that compares as its fields in order.

    A NamedTuple rather than a dataclass: heap operations compare entries all the time,
    and a tuple compares in C. 200,000 pushes and pops took 0.50 s as NamedTuples and
    1.50 s as an ordered frozen dataclass (0.37 s as bare tuples, read by position).
    """

    cost: float  #: fresh: the merge's cost; stale: an estimate (a key, not a cost)
    rank: int  #: TIE_RANK of the kind
    order: int  #: push order, unique
    kind: MergeKind
    a: int  #: first primitive: a patch (PP), the curve (CP), a curve (CC)
    b: int  #: second primitive: a patch (PP, CP), a curve (CC)
    fresh: bool  #: whether ``cost`` was worked out for this very pair


class MergeQueue:
    """A heap of :class:`QueueEntry`, with look-ahead and compaction."""

    def __init__(self) -> None:
        self._heap: list[QueueEntry] = []
        self._pushed = 0
        self._compacted_size = COMPACT_MIN

    def __len__(self) -> int:
        return len(self._heap)

    def push(self, cost: float, kind: MergeKind, a: int, b: int, fresh: bool) -> None:
        """Queue a pair; an infinite cost (the pair may not merge) is not queued."""
        if cost < math.inf:
            heapq.heappush(self._heap, QueueEntry(cost, TIE_RANK[kind], self._pushed, kind,
                                                  a, b, fresh))
            self._pushed += 1

    def pop(self) -> QueueEntry:
        return heapq.heappop(self._heap)

    def next_entries(self, count: int) -> list[QueueEntry]:
        """The next ``count`` entries in pop order, left in the queue (popped and pushed
        back: ``heapq.nsmallest`` would scan the whole heap, tens of thousands of entries
        on a dense sketch)."""
        entries = [heapq.heappop(self._heap) for _ in range(min(count, len(self._heap)))]
        for entry in entries:
            heapq.heappush(self._heap, entry)
        return entries

    def compact(self, alive: Callable[[QueueEntry], bool]) -> bool:
        """Drop the entries that are not ``alive`` once the queue has doubled since the last
        compaction; returns whether it compacted. The order of the rest is kept."""
        if len(self._heap) <= 2 * self._compacted_size:
            return False
        self._heap = [e for e in self._heap if alive(e)]
        heapq.heapify(self._heap)
        self._compacted_size = max(len(self._heap), COMPACT_MIN)
        return True
