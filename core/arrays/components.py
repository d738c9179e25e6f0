"""Connected components of a graph given as pairs (union-find), for noding and snapping."""

from __future__ import annotations

from collections.abc import Iterable
from functools import partial

import numpy as np

__all__ = ["component_labels", "kept_apart_labels"]


def _root(parent: list[int], a: int) -> int:
    """The root of ``a`` in the union-find forest ``parent``, halving the path to it."""
    while parent[a] != a:
        parent[a] = parent[parent[a]]
        a = parent[a]
    return a


def _labels(parent: list[int]) -> np.ndarray:
    """Each item's component as 0..k-1, numbered in order of each one's smallest item."""
    roots = np.array([_root(parent, a) for a in range(len(parent))], dtype=np.intp)
    return np.unique(roots, return_inverse=True)[1]


def component_labels(n: int, pairs: np.ndarray | Iterable[np.ndarray]) -> np.ndarray:
    """Labels 0..k-1 of ``n`` items such that the two items of every pair share one.

    ``pairs`` is a (m, 2) array or an iterable of such arrays (chunks, so that a huge set
    of pairs need not exist at once). Labels are numbered in order of each component's
    smallest item.
    """
    parent = list(range(n))
    find = partial(_root, parent)
    chunks = [pairs] if isinstance(pairs, np.ndarray) else pairs
    for chunk in chunks:
        for a, b in np.asarray(chunk, dtype=np.intp).reshape(-1, 2).tolist():
            ra, rb = find(a), find(b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
    return _labels(parent)


def kept_apart_labels(n: int, pairs: np.ndarray, apart: np.ndarray) -> np.ndarray:
    """Labels 0..k-1 of ``n`` items joined through ``pairs`` in their order, a pair
    skipped where it would put in one component the two items of a pair marked in
    ``apart`` (a cannot-link constraint: (m,) bools, one per pair; such pairs are never
    joined). Without a pair marked, :func:`component_labels`. Labels are numbered in order
    of each component's smallest item.

    >>> pairs = np.array([[0, 1], [1, 2], [0, 2], [2, 3]])
    >>> kept_apart_labels(4, pairs, np.array([False, False, True, False])).tolist()
    [0, 0, 1, 1]
    >>> kept_apart_labels(4, pairs, np.zeros(4, bool)).tolist()
    [0, 0, 0, 0]
    """
    pairs = np.asarray(pairs, dtype=np.intp).reshape(-1, 2)
    if not np.any(apart):
        return component_labels(n, pairs)
    parent = list(range(n))
    avoid: dict[int, set[int]] = {}  # per root, items its component must not join
    for a, b in pairs[apart].tolist():
        avoid.setdefault(a, set()).add(b)
        avoid.setdefault(b, set()).add(a)
    find = partial(_root, parent)
    for a, b in pairs[~apart].tolist():
        ra, rb = find(a), find(b)
        if ra == rb:
            continue
        held_a, held_b = avoid.get(ra, ()), avoid.get(rb, ())
        if any(find(x) == rb for x in held_a) or any(find(x) == ra for x in held_b):
            continue
        root, other = min(ra, rb), max(ra, rb)
        parent[other] = root
        if held_a or held_b:
            avoid[root] = set(held_a) | set(held_b)
            avoid.pop(other, None)
    return _labels(parent)
