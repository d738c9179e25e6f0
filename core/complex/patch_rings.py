"""Patch outlines as rings of half-edges, their union, and their points.

Half-edge ``2c`` walks curve ``c`` forward, ``2c + 1`` backward; a ring lists half-edges in
order with its face on the left. A patch has one outer ring (counter-clockwise, positive
area) and clockwise hole rings. Two adjacent patches are united by deleting the half-edges
of the curves they share and relinking their neighbours, exactly as in a doubly connected
edge list; the outer ring of the union is the resulting cycle of largest area.
"""

from __future__ import annotations

import numpy as np

from ..arrays.geometry import shoelace_terms
from .base_complex import BaseComplex, Ring

__all__ = [
    "half_edges", "Outline", "RingGeometry", "spike_walk", "union_outline_points", "union_rings",
]


def half_edges(ring: Ring) -> list[int]:
    return [2 * c + (0 if fwd else 1) for c, fwd in ring]


class RingGeometry:
    """Points and areas of half-edge rings over the base complex's curves.

    Each half-edge's points (its curve without the last point, walked its way) are laid
    out once in one array, so that a ring's points are gathered with one index array
    rather than a slice and a copy per half-edge: grown patches have long rings."""

    def __init__(self, cx: BaseComplex) -> None:
        self.curves = cx.curves
        self.curve_nodes = cx.curve_nodes
        cross = shoelace_terms(cx.curves) if cx.curves else np.empty(0)
        self.half_area = np.repeat(cross, 2) * np.tile([1.0, -1.0], len(cross))
        parts = [part for c in cx.curves for part in (c[:-1], c[:0:-1])]
        self.half_len = np.fromiter(map(len, parts), dtype=np.intp, count=len(parts))
        self.half_start = np.cumsum(self.half_len) - self.half_len
        self.flat = np.concatenate(parts) if parts else np.empty((0, 2))

    def origin(self, h: int) -> int:
        return int(self.curve_nodes[h >> 1, h & 1])

    def area(self, ring: list[int]) -> float:
        return float(self.half_area[ring].sum())

    def points(self, ring: list[int]) -> np.ndarray:
        """The ring's points in order, the first point not repeated at the end."""
        return self.flat[self.index_of(np.asarray(ring))[0]]

    def index_of(self, ring: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Indices into ``flat`` of the ring's points, and where each half-edge starts."""
        lens = self.half_len[ring]
        ends = np.cumsum(lens)
        first = ends - lens
        total = int(ends[-1]) if len(ends) else 0
        return np.repeat(self.half_start[ring] - first, lens) + np.arange(total), first

    def with_spike(self, ring: list[int], node: int, spike: np.ndarray) -> np.ndarray:
        """Ring points with ``spike`` (a walk out from ``node`` and back) inserted there."""
        points = self.points(ring)
        at = next((i for i, h in enumerate(ring) if self.origin(h) == node), None)
        if at is None:
            return points
        k = int(self.half_len[ring[:at]].sum())
        return np.concatenate([points[:k], spike[:-1], points[k:]])


def spike_walk(points: np.ndarray, anchor: np.ndarray) -> np.ndarray:
    """A curve walked from ``anchor`` via its nearest point to both ends and back, closed."""
    n = len(points)
    k = int(np.argmin(np.hypot(*(points - anchor).T)))
    idx = np.concatenate([np.arange(k, n), np.arange(n - 2, k - 1, -1),
                          np.arange(k - 1, -1, -1), np.arange(1, k + 1)])
    walk = np.concatenate([anchor[None], points[idx], anchor[None]])
    keep = np.concatenate([[True], np.hypot(*np.diff(walk, axis=0).T) > 0])
    keep[-1] = True
    return walk[keep]


def union_rings(rings_p: list[list[int]], rings_q: list[list[int]], shared: list[int],
                geometry: RingGeometry) -> list[list[int]]:
    """Rings of the union of two patches sharing ``shared`` curves; outer ring first."""
    succ: dict[int, int] = {}
    for ring in rings_p + rings_q:
        n = len(ring)
        for i, h in enumerate(ring):
            succ[h] = ring[(i + 1) % n]
    pred = {v: k for k, v in succ.items()}
    for c in shared:
        g, t = 2 * c, 2 * c + 1
        if g not in succ or t not in succ:
            continue
        pg, sg, pt, st = pred[g], succ[g], pred[t], succ[t]
        links = []
        if sg == t and st == g:
            pass  # a closed curve alone between the two: nothing left to link
        elif sg == t:
            links.append((pg, st))
        elif st == g:
            links.append((pt, sg))
        else:
            links += [(pg, st), (pt, sg)]
        for h in (g, t):
            del succ[h]
            del pred[h]
        for x, y in links:
            succ[x] = y
            pred[y] = x
    rings: list[list[int]] = []
    seen: set[int] = set()
    for start in succ:
        if start in seen:
            continue
        ring = []
        h = start
        while h not in seen:
            seen.add(h)
            ring.append(h)
            h = succ[h]
        rings.append(ring)
    rings.sort(key=geometry.area, reverse=True)
    return rings


class Outline:
    """A patch's outer ring as arrays, for quick unions with a neighbour."""

    def __init__(self, ring: list[int], geometry: RingGeometry) -> None:
        self.half = ring
        self.pos = dict(zip(ring, range(len(ring))))
        index, first = geometry.index_of(np.asarray(ring))
        self.start = np.append(first, len(index))
        self.points = geometry.flat[index]

    def arc(self, first: int, last: int) -> np.ndarray:
        """Points of the half-edges ``first`` to ``last`` (cyclic, inclusive)."""
        a, b = self.start[first], self.start[last + 1]
        if first <= last:
            return self.points[a:b]
        return np.concatenate([self.points[a:], self.points[:b]])


def _cyclic_run(positions: list[int], n: int) -> tuple[int, int] | None:
    """(first, last) when the positions form one unbroken cyclic run shorter than n."""
    s = sorted(positions)
    k = len(s)
    if k == 0 or k >= n:
        return None
    breaks = [i for i in range(k) if (s[(i + 1) % k] - s[i]) % n != 1]
    if len(breaks) != 1:
        return None
    return s[(breaks[0] + 1) % k], s[breaks[0]]


def union_outline_points(op: Outline, oq: Outline, shared: list[int]) -> np.ndarray | None:
    """Outer ring points of the union of two patches sharing one run of outer-ring curves.

    The union walks p's ring from where the shared run ends to where it starts, then q's
    the same way; holes are left out, as they do not change the outer ring. None when the
    shared curves are not one run on both outer rings (the general :func:`union_rings`
    handles those).
    """
    hp = [op.pos[h] for c in shared for h in (2 * c, 2 * c + 1) if h in op.pos]
    hq = [oq.pos[h] for c in shared for h in (2 * c, 2 * c + 1) if h in oq.pos]
    if len(hp) != len(shared) or len(hq) != len(shared):
        return None
    rp, rq = _cyclic_run(hp, len(op.half)), _cyclic_run(hq, len(oq.half))
    if rp is None or rq is None:
        return None
    arc_p = op.arc((rp[1] + 1) % len(op.half), (rp[0] - 1) % len(op.half))
    arc_q = oq.arc((rq[1] + 1) % len(oq.half), (rq[0] - 1) % len(oq.half))
    return np.concatenate([arc_p, arc_q])
