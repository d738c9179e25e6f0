"""Connected components of a graph given as pairs (union-find), for noding and snapping."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

__all__ = ["component_labels"]


def component_labels(n: int, pairs: np.ndarray | Iterable[np.ndarray]) -> np.ndarray:
    """Labels 0..k-1 of ``n`` items such that the two items of every pair share one.

    ``pairs`` is a (m, 2) array or an iterable of such arrays (chunks, so that a huge set
    of pairs need not exist at once). Labels are numbered in order of each component's
    smallest item.
    """
    parent = list(range(n))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    chunks = [pairs] if isinstance(pairs, np.ndarray) else pairs
    for chunk in chunks:
        for a, b in np.asarray(chunk, dtype=np.intp).reshape(-1, 2).tolist():
            ra, rb = find(a), find(b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([find(a) for a in range(n)], dtype=np.intp)
    return np.unique(roots, return_inverse=True)[1]
