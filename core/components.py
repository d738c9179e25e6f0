"""Connected components of a graph given as pairs (union-find), for noding and snapping."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import shapely


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

    labels = component_labels(len(unique), pairs())[inverse.ravel()]
    _, first, inverse = np.unique(labels, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse.ravel()]


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
    count = np.bincount(labels)
    mean = np.zeros((len(count), points.shape[1]))
    np.add.at(mean, labels, points)
    mean /= count[:, None]
    far = np.hypot(*(points - mean[labels]).T) > radius
    wide = np.unique(labels[far])
    if not len(wide):
        return labels
    members = np.flatnonzero(np.isin(labels, wide))
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
    labels = labels.copy()
    labels[members] = taken
    _, first, inverse = np.unique(labels, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse.ravel()]
