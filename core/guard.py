"""The distance guard: whatever a merge removes must lie within d_eps of what stays.

``covered(curves, allowed)`` asks whether every sample of ``curves`` lies within d_eps of
one of the ``allowed`` curves. Base curves never change shape, so for a base curve the
nearby base curves that each cover all of it are found once, on first use; one of them
among the allowed settles the question without geometry. Only what that cannot settle is
measured, exactly.
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
        self._cover: dict[int, set[int]] = {}
        self._near: dict[int, frozenset[int]] = {}  # curves whose box meets c's, widened
        self._verdicts: dict[tuple, bool] = {}

    def cover(self, c: int) -> set[int]:
        """Base curves (other than ``c``) within d_eps of every sample of base curve ``c``."""
        if c not in self._cover:
            pts = self.samples[c]
            lo, hi = pts.min(axis=0) - self.d_eps, pts.max(axis=0) + self.d_eps
            near = self.tree.query(shapely.box(*lo, *hi))  # a box query is quick; the
            near = near[near != c]                         # distances below decide
            d = shapely.distance(shapely.points(pts)[:, None], self.lines[near][None, :])
            self._cover[c] = set(near[d.max(axis=0) <= self.d_eps].tolist())
            self._near[c] = frozenset(near.tolist())
        return self._cover[c]

    def covered(self, removed: list[int], allowed: set[int], extra: np.ndarray | None = None
                ) -> bool:
        """Every sample of the ``removed`` base curves (and of ``extra`` points) within
        d_eps of the ``allowed`` base curves."""
        if not allowed:
            return False
        unsettled = [c for c in removed if not self.cover(c) & allowed]
        if not unsettled and extra is None:
            return True
        if extra is None:
            # only allowed curves near the removed ones can matter: a verdict given for the
            # same removed curves and the same nearby allowed curves stands
            key = (tuple(unsettled), frozenset().union(*(self._near[c] for c in unsettled))
                   & allowed)
            if key not in self._verdicts:
                self._verdicts[key] = self._measure(unsettled, key[1], None)
            return self._verdicts[key]
        return self._measure(unsettled, allowed, extra)

    def _measure(self, removed: list[int], allowed: set[int] | frozenset[int],
                 extra: np.ndarray | None) -> bool:
        pts = [self.samples[c] for c in removed] + ([extra] if extra is not None else [])
        points = np.concatenate(pts)
        lo, hi = points.min(axis=0) - self.d_eps, points.max(axis=0) + self.d_eps
        cand = [c for c in self.tree.query(shapely.box(*lo, *hi)).tolist() if c in allowed]
        if not cand:
            return False
        d = shapely.distance(shapely.points(points)[:, None], self.lines[cand][None, :])
        return bool(d.min(axis=1).max() <= self.d_eps)
