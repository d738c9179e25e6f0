"""What the line stage keeps between runs of one result: a slider replays the merge
history at other epsilons, and the states it passes through share most output lines with
each other.

Every store is keyed by content (a polyline's bytes, with what else the value depends on)
and holds a value that depends on its key alone, so a hit and a miss give the same result
to the bit. Each store is bounded, least recently used first out: a long slider session
on a large drawing would otherwise keep every state it ever passed through. Code reading
a store never counts on a value it put there earlier staying: the pass keeps what it needs
for itself and only asks the memo first.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Hashable
from dataclasses import dataclass, field
from typing import Generic, TypeVar

import numpy as np

__all__ = ["GROUP_ENTRIES", "MEMO_ENTRIES", "LruStore", "StrokeMemo", "shape_key"]

K = TypeVar("K", bound=Hashable)
V = TypeVar("V")

#: entries each store keeps: a bound for slider sessions far longer than a run and a few
#: replays (docs/decisions.md, "memo entries").
MEMO_ENTRIES = 200_000

#: the entries of the store of group fits, each a line of the drawing (a few KB): a
#: replay asks for about as many as a run makes, and keeps within some tens of MB
GROUP_ENTRIES = 20_000


class LruStore(Generic[K, V]):
    """A mapping that keeps at most ``size`` entries, dropping the least recently used.

    >>> store = LruStore(2)
    >>> store.put("a", 1); store.put("b", 2); _ = store.get("a"); store.put("c", 3)
    >>> sorted(store.keys())
    ['a', 'c']
    """

    def __init__(self, size: int = MEMO_ENTRIES) -> None:
        self.size = size
        self._data: OrderedDict[K, V] = OrderedDict()

    def __len__(self) -> int:
        return len(self._data)

    def __contains__(self, key: K) -> bool:
        return key in self._data

    def keys(self):
        return self._data.keys()

    def get(self, key: K, default: V | None = None) -> V | None:
        """The value kept for ``key`` (now the most recently used), or ``default``."""
        if key not in self._data:
            return default
        self._data.move_to_end(key)
        return self._data[key]

    def put(self, key: K, value: V) -> None:
        self._data[key] = value
        self._data.move_to_end(key)
        while len(self._data) > self.size:
            self._data.popitem(last=False)

    __setitem__ = put  # so that code keeping a plain dict may be given a store


def shape_key(points: np.ndarray, closed: bool = False) -> bytes:
    """A polyline by content, open or closed, as the stores key what is made of it."""
    return points.tobytes() + (b"c" if closed else b"o")


@dataclass
class StrokeMemo:
    """The line stage's stores, shared by a result and every replay of it."""

    #: Bezier fit of a resampled output stroke (shape_key of it before smoothing; the
    #: smoothing depends on it and the result's params alone): control points and the
    #: polyline sampled from them
    fits: LruStore[bytes, tuple[np.ndarray, np.ndarray]] = field(default_factory=LruStore)
    #: what pass 4 finds of a set of pieces (:class:`core.lines.fit.GroupFit`), by
    #: whether anything merged (at epsilon 0 the pieces are the strokes uncut) and the
    #: pieces' indices: the pieces are the input strokes cut by the result's params, the
    #: same in every replay above epsilon 0
    groups: LruStore[tuple[bool, tuple[int, ...]], object] = field(
        default_factory=lambda: LruStore(GROUP_ENTRIES))
    #: whether two pieces run along each other and then part (pass 4,
    #: :func:`core.lines.along.parting`), by whether anything merged and their indices
    parting: LruStore[tuple[bool, int, int], bool] = field(default_factory=LruStore)
    #: pass 1's pieces, the input stroke and place in it of each, by whether anything
    #: merged: a function of the strokes and the result's params alone
    pieces: LruStore[bool, tuple] = field(default_factory=lambda: LruStore(2))
    #: pass 2's samples and the states it followed last
    #: (:class:`core.lines.follow.FollowMemo`), by whether anything merged
    follow: LruStore[bool, object] = field(default_factory=lambda: LruStore(2))
    #: what pass 5 finds of two lines (:class:`core.lines.join.Judged`), by their pieces'
    #: indices (each line the fit of its pieces)
    judged: LruStore[tuple[tuple[int, ...], tuple[int, ...]], object] = field(
        default_factory=LruStore)
    #: how far a line's own ink spreads from it (:func:`core.lines.join.half_width`), by
    #: its pieces' indices (passes 5 and 6, which run only above epsilon 0, where a line
    #: is the fit of its pieces)
    widths: LruStore[tuple[int, ...], float] = field(default_factory=LruStore)
    #: how far a joint fit moves the lines it joins (:func:`core.lines.fit._joint_fits`),
    #: by the lines' pieces and the joint lines' pieces (pass 5, each line the fit of its
    #: pieces)
    moves: LruStore[tuple, float] = field(default_factory=LruStore)
    #: the gap between two lines (:func:`core.lines.join.one_band`), by the shorter's and
    #: the longer's pieces' indices (passes 5 and 6, as ``widths``)
    gaps: LruStore[tuple[tuple[int, ...], tuple[int, ...]], float] = field(
        default_factory=LruStore)
