"""The distance guard: whatever a patch merge removes must lie within a reach of what stays
(``Tuning.guard_reach`` d_eps, :class:`core.params.Tuning`).

``covered(curves, allowed)`` asks whether every sample of ``curves`` lies within the reach
of one of the ``allowed`` curves. Base curves never change shape, so for a base curve the
nearby base curves that each cover all of it are found once, on first use; one of them
among the allowed settles the question without geometry. Only what that cannot settle is
measured, exactly.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..arrays.polylines import resample_polyline
from .curve_merge import sample_spacing

__all__ = ["CurveSamples", "DistanceGuard", "PatchCurves"]


class PatchCurves:
    """The curves of two patches except the ones they share, as a view: a big patch has
    thousands of curves and the guard only asks about a few of them."""

    def __init__(self, p: set[int], q: set[int], shared: list[int]) -> None:
        self.p, self.q, self.shared = p, q, set(shared)

    def __contains__(self, c: int) -> bool:
        return (c in self.p or c in self.q) and c not in self.shared

    def __bool__(self) -> bool:
        return len(self.p) + len(self.q) - 2 * len(self.shared) > 0


class CurveSamples:
    """Each curve resampled evenly, on first use: a dense sketch has tens of thousands of
    curves, and most are never measured."""

    def __init__(self, curves: list[np.ndarray], spacing: float) -> None:
        self.curves, self.spacing = curves, spacing
        self._made: list[np.ndarray | None] = [None] * len(curves)

    def __len__(self) -> int:
        return len(self.curves)

    def __getitem__(self, c: int) -> np.ndarray:
        made = self._made[c]
        if made is None:
            made = self._made[c] = resample_polyline(self.curves[c], self.spacing)
        return made


def _allowed_one(curves: np.ndarray | frozenset[int],
                 allowed: set[int] | PatchCurves) -> int | None:
    """One of ``curves`` that is allowed, or None; with set operations, not a loop."""
    ids = curves if isinstance(curves, frozenset) else set(curves.tolist())
    if isinstance(allowed, PatchCurves):
        hits = ((ids & allowed.p) | (ids & allowed.q)) - allowed.shared
    else:
        hits = allowed.intersection(ids)
    return min(hits) if hits else None


class DistanceGuard:
    def __init__(self, curves: list[np.ndarray], lines: np.ndarray, d_eps: float,
                 curve_nodes: np.ndarray, node_curves: list[list[int]], reach: float) -> None:
        """``curve_nodes`` (E, 2) and ``node_curves`` as in :class:`BaseComplex`; curves are
        sampled as curve-curve pairing samples them at ``d_eps``, and measured against
        ``reach``."""
        self.reach = reach
        self.lines = lines
        self.tree = shapely.STRtree(lines)
        # at the spacing curve-curve pairing samples at, so that it can reuse these
        self.samples = CurveSamples(curves, sample_spacing(d_eps))
        # a curve no longer than the reach lies within it of its end nodes, so within it of
        # any curve through one of them: settled without geometry (dense sketches are
        # mostly such crumbs between crossings)
        self.short = shapely.length(lines) <= self.reach if len(lines) else np.zeros(0, bool)
        self.curve_nodes, self.node_curves = curve_nodes, node_curves
        # kept as small int arrays: in a dense sketch a curve has a hundred covers, and
        # Python sets of them would take hundreds of MB
        self._cover: dict[int, np.ndarray] = {}
        self._near: dict[int, np.ndarray] = {}  # curves whose box meets c's, widened
        self._ends: dict[int, frozenset[int]] = {}  # curves through c's end nodes
        self._near_points: dict[tuple[float, float], np.ndarray] = {}  # curves near a point
        self._witness: dict[int, int] = {}  # an allowed curve that last covered c
        self._verdicts: dict[tuple, bool] = {}

    def cover(self, c: int) -> np.ndarray:
        """Base curves (other than ``c``) within the reach of every sample of base curve ``c``.

        The curves near each end are asked of the index once per end point, as most curves
        of a dense sketch are crumbs between crossings sharing their ends with others;
        the few near both ends are then measured against the samples between."""
        if c not in self._cover:
            pts = self.samples[c]
            found = np.intersect1d(self._near_point(pts[0]), self._near_point(pts[-1]),
                                   assume_unique=True)
            found = found[found != c]
            if len(pts) > 2 and len(found):
                within = shapely.dwithin(shapely.points(pts[1:-1])[:, None],
                                         self.lines[found][None, :], self.reach)
                found = found[within.all(axis=0)]
            self._cover[c] = found
        return self._cover[c]

    def _near_point(self, point: np.ndarray) -> np.ndarray:
        """Base curves within the reach of a point (sorted), asked once per point."""
        key = (float(point[0]), float(point[1]))
        if key not in self._near_points:
            near = self.tree.query(shapely.points(point), predicate="dwithin",
                                   distance=self.reach)
            self._near_points[key] = np.sort(near).astype(np.int32)
        return self._near_points[key]

    def _through_ends(self, c: int) -> frozenset[int]:
        """Base curves (other than ``c``) through one of the end nodes of curve ``c``."""
        if c not in self._ends:
            a, b = self.curve_nodes[c]
            self._ends[c] = frozenset({*self.node_curves[a], *self.node_curves[b]} - {c})
        return self._ends[c]

    def near(self, c: int) -> np.ndarray:
        """Base curves (other than ``c``) whose boxes meet c's widened by the reach."""
        if c not in self._near:
            pts = self.samples[c]
            lo, hi = pts.min(axis=0) - self.reach, pts.max(axis=0) + self.reach
            near = self.tree.query(shapely.box(*lo, *hi))
            self._near[c] = near[near != c].astype(np.int32)
        return self._near[c]

    def covered(self, removed: list[int], allowed: set[int] | PatchCurves,
                extra: np.ndarray | None = None) -> bool:
        """Every sample of the ``removed`` base curves (and of ``extra`` points) within
        the reach of the ``allowed`` base curves."""
        if not allowed:
            return False
        unsettled = [c for c in removed if not self._settled(c, allowed)]
        if not unsettled and extra is None:
            return True
        if extra is None:
            # only allowed curves near the removed ones can matter: a verdict given for the
            # same removed curves and the same nearby allowed curves stands
            near = np.unique(np.concatenate([self.near(c) for c in unsettled])).tolist()
            key = (tuple(unsettled), frozenset(c for c in near if c in allowed))
            if key not in self._verdicts:
                self._verdicts[key] = self._measure(unsettled, key[1], None)
            return self._verdicts[key]
        return self._measure(unsettled, allowed, extra)

    def _settled(self, c: int, allowed: set[int] | PatchCurves) -> bool:
        """Whether an allowed curve covers base curve ``c`` by itself: one through an end
        node of a crumb, or one of its covers. The last one found is tried first: growing
        patches ask about the same curves again and again, and it mostly still stands."""
        witness = self._witness.get(c)
        if witness is not None and witness in allowed:
            return True
        witness = None
        if self.short[c]:
            witness = _allowed_one(self._through_ends(c), allowed)
        if witness is None:
            witness = _allowed_one(self.cover(c), allowed)
        if witness is None:
            return False
        self._witness[c] = witness
        return True

    def _measure(self, removed: list[int], allowed: set[int] | frozenset[int] | PatchCurves,
                 extra: np.ndarray | None) -> bool:
        pts = [self.samples[c] for c in removed] + ([extra] if extra is not None else [])
        points = np.concatenate(pts)
        lo, hi = points.min(axis=0) - self.reach, points.max(axis=0) + self.reach
        cand = [c for c in self.tree.query(shapely.box(*lo, *hi)).tolist() if c in allowed]
        if not cand:
            return False
        near = shapely.dwithin(shapely.points(points)[:, None], self.lines[cand][None, :],
                               self.reach)
        return bool(near.any(axis=1).all())
