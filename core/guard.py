"""The distance guard: whatever a merge removes must lie within d_eps of what stays.

``covered(curves, allowed)`` asks whether every sample of ``curves`` lies within d_eps of
one of the ``allowed`` curves. Base curves never change shape, so for each base curve the
largest distance of its samples to each nearby base curve is tabled once; a single allowed
curve that covers a removed curve on its own settles the question without geometry. Only
what the table cannot settle is measured, exactly.
"""

from __future__ import annotations

import numpy as np
import shapely

from .geometry import resample_polyline


class DistanceGuard:
    def __init__(self, curves: list[np.ndarray], lines: np.ndarray, d_eps: float) -> None:
        self.d_eps = d_eps
        self.lines = lines
        self.tree = shapely.STRtree(lines)
        self.samples = [resample_polyline(c, d_eps / 2) for c in curves]
        self.cover: dict[int, set[int]] = {}  # curve -> base curves within d_eps of all of it
        if len(curves) < 2:
            return
        a, b = self.tree.query(lines, predicate="dwithin", distance=d_eps)
        keep = a != b
        a, b = a[keep], b[keep]
        counts = np.array([len(s) for s in self.samples])
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        points = shapely.points(np.concatenate(self.samples))  # each sample made once
        owner = np.repeat(np.arange(len(a)), counts[a])  # pair of each (sample, line) row
        local = np.arange(len(owner)) - np.repeat(np.cumsum(counts[a]) - counts[a], counts[a])
        d = shapely.distance(points[starts[a][owner] + local], lines[b[owner]])
        worst = np.full(len(a), -np.inf)
        np.maximum.at(worst, owner, d)
        for x, y in zip(a[worst <= d_eps].tolist(), b[worst <= d_eps].tolist()):
            self.cover.setdefault(x, set()).add(y)

    def covered(self, removed: list[int], allowed: set[int], extra: np.ndarray | None = None
                ) -> bool:
        """Every sample of the ``removed`` base curves (and of ``extra`` points) within
        d_eps of the ``allowed`` base curves."""
        if not allowed:
            return False
        unsettled = [c for c in removed if not self.cover.get(c, set()) & allowed]
        if not unsettled and extra is None:
            return True
        pts = [self.samples[c] for c in unsettled] + ([extra] if extra is not None else [])
        points = np.concatenate(pts)
        lo, hi = points.min(axis=0) - self.d_eps, points.max(axis=0) + self.d_eps
        cand = [c for c in self.tree.query(shapely.box(*lo, *hi)).tolist() if c in allowed]
        if not cand:
            return False
        d = shapely.distance(shapely.points(points)[:, None], self.lines[cand][None, :])
        return bool(d.min(axis=1).max() <= self.d_eps)
