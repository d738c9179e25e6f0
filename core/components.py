"""Connected components of a graph given as pairs (union-find), for noding and snapping."""

from __future__ import annotations

import numpy as np


def component_labels(n: int, pairs: np.ndarray) -> np.ndarray:
    """Labels 0..k-1 of ``n`` items such that the two items of every pair share one.

    Labels are numbered in order of each component's smallest item.
    """
    parent = list(range(n))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in np.asarray(pairs, dtype=np.intp).reshape(-1, 2).tolist():
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([find(a) for a in range(n)], dtype=np.intp)
    return np.unique(roots, return_inverse=True)[1]
