"""Connected components of a graph given as pairs (union-find), for noding and snapping."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import shapely

__all__ = [
    "cluster_labels", "component_labels", "group_means", "tight_cluster_labels", "wider_than",
]


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


def cluster_labels(points: np.ndarray, radius: float, chunk: int = 4096) -> np.ndarray:
    """Labels of ``points`` such that any two within ``radius`` share one (single linkage),
    numbered in order of each cluster's first point.

    Equal points are merged first (many ends meet at a busy junction, and their pairs grow
    with the square of its degree), and the neighbours within ``radius`` are found a chunk
    of points at a time, so that memory stays bounded however dense the points are.
    """
    unique, inverse = np.unique(points, axis=0, return_inverse=True)
    geoms = shapely.points(unique)
    tree = shapely.STRtree(geoms)

    def pairs():
        for k in range(0, len(geoms), chunk):
            i, j = tree.query(geoms[k:k + chunk], predicate="dwithin", distance=radius)
            i = i + k
            yield np.stack([i[i < j], j[i < j]], axis=1)

    return _numbered_by_first(component_labels(len(unique), pairs())[inverse.ravel()])


def tight_cluster_labels(points: np.ndarray, radius: float, chunk: int = 4096) -> np.ndarray:
    """Labels of ``points`` such that any two within ``radius`` share one, as long as
    the clusters stay small: each within ``radius`` of its mean, or of its first point.

    Single linkage chains: ends spaced along two close parallel lines would all be one
    cluster, and moving them to its mean would pull a whole stretch of drawing to one
    point. A cluster with a point farther than ``radius`` from its mean is split instead,
    greedily in the order of its points: each point not yet taken gathers the points
    within ``radius`` of it not yet taken.
    """
    labels = cluster_labels(points, radius)
    wide = wider_than(points, labels, radius)
    if not wide.any():
        return labels
    members = np.flatnonzero(wide[labels])
    geoms = shapely.points(points[members])
    tree = shapely.STRtree(geoms)
    taken = np.full(len(members), -1)
    top = labels.max() + 1
    for start in range(0, len(members), chunk):  # neighbours a chunk at a time, as above
        i, j = tree.query(geoms[start:start + chunk], predicate="dwithin", distance=radius)
        near = np.split(j, np.searchsorted(i, np.arange(1, min(chunk, len(members) - start))))
        for k, group in enumerate(near, start):
            if taken[k] < 0:
                taken[group[taken[group] < 0]] = top
                top += 1
    labels[members] = taken
    return _numbered_by_first(labels)


def group_means(points: np.ndarray, labels: np.ndarray) -> np.ndarray:
    """The mean of each group's points (labels 0..k-1, each used)."""
    sums = np.zeros((labels.max() + 1, points.shape[1]))
    np.add.at(sums, labels, points)
    return sums / np.bincount(labels)[:, None]


def wider_than(points: np.ndarray, labels: np.ndarray, radius: float) -> np.ndarray:
    """Whether each group has a point farther than ``radius`` from the group's mean."""
    far = np.hypot(*(points - group_means(points, labels)[labels]).T) > radius
    return np.bincount(labels[far], minlength=labels.max() + 1) > 0


def _numbered_by_first(labels: np.ndarray) -> np.ndarray:
    """The same grouping, numbered 0..k-1 in order of each group's first item."""
    _, first, inverse = np.unique(labels, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse.ravel()]
