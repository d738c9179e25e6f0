"""Small vectorised helpers between ragged lists of polylines and shapely geometry arrays."""

from __future__ import annotations

import numpy as np
import shapely


def _flat(polylines: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    counts = np.fromiter((len(p) for p in polylines), dtype=np.intp, count=len(polylines))
    coords = np.concatenate(polylines) if polylines else np.empty((0, 2))
    return coords, np.repeat(np.arange(len(polylines)), counts)


def lines_from(polylines: list[np.ndarray]) -> np.ndarray:
    """One LineString per (k >= 2, 2) polyline, in one vectorised call."""
    coords, index = _flat(polylines)
    return shapely.linestrings(coords, indices=index)


def polygons_from(rings: list[np.ndarray]) -> np.ndarray:
    """One Polygon per ring (first point not repeated; shapely closes it)."""
    closed = [np.concatenate([r, r[:1]]) for r in rings]
    coords, index = _flat(closed)
    return shapely.polygons(shapely.linearrings(coords, indices=index))


def shoelace_terms(curves: list[np.ndarray]) -> np.ndarray:
    """Each polyline's term 1/2 sum(x_i y_i+1 - x_i+1 y_i) of the shoelace formula: the
    signed area of a ring is the sum of the terms of the curves walked round it (minus a
    curve's term where it is walked backwards).

    >>> shoelace_terms([np.array([[0., 0], [1, 0], [1, 1]]), np.array([[1., 1], [0, 0]])])
    array([0.5, 0. ])
    """
    counts = np.fromiter((len(c) for c in curves), dtype=np.intp, count=len(curves))
    pts = np.concatenate(curves)
    cross = pts[:-1, 0] * pts[1:, 1] - pts[1:, 0] * pts[:-1, 1]
    owner = np.repeat(np.arange(len(curves)), counts)[:-1]
    same = owner == np.repeat(np.arange(len(curves)), counts)[1:]
    return 0.5 * np.bincount(owner[same], weights=cross[same], minlength=len(curves))


def ring_is_counter_clockwise(points: np.ndarray) -> bool:
    """Whether a closed ring (first point not repeated) has positive signed area.

    >>> ring_is_counter_clockwise(np.array([[0., 0], [1, 0], [0, 1]]))
    True
    """
    x, y = points[:, 0], points[:, 1]
    return bool(x[:-1] @ y[1:] - x[1:] @ y[:-1] + x[-1] * y[0] - x[0] * y[-1] > 0)


def split_coordinates(geoms: np.ndarray) -> list[np.ndarray]:
    """The coordinates of each geometry, as a list of (k, 2) arrays."""
    coords, index = shapely.get_coordinates(geoms, return_index=True)
    cuts = np.flatnonzero(np.diff(index)) + 1
    return np.split(coords, cuts) if len(coords) else []


def arc_lengths(points: np.ndarray) -> np.ndarray:
    """Cumulative arc length at each point, starting at 0."""
    d = points[1:] - points[:-1]
    s = np.empty(len(points))
    s[0] = 0.0
    np.cumsum(np.hypot(d[:, 0], d[:, 1]), out=s[1:])
    return s


def resample_polyline(points: np.ndarray, spacing: float) -> np.ndarray:
    """Points evenly spaced by arc length (at most ``spacing`` apart), ends kept; a closed
    polyline keeps at least four, so that it stays a loop however short."""
    s = arc_lengths(points)
    closed = len(points) > 2 and points[0, 0] == points[-1, 0] and points[0, 1] == points[-1, 1]
    n = max(4 if closed else 2, int(np.ceil(s[-1] / spacing)) + 1)
    t = np.arange(n) * (s[-1] / (n - 1))
    t[-1] = s[-1]
    return points_at(t, s, points)


def points_at(t: np.ndarray, s: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The polyline ``points``, whose arc length at each point is ``s``, at arc lengths
    ``t`` (linear between its points)."""
    out = np.empty((len(t), 2))
    out[:, 0] = np.interp(t, s, points[:, 0])
    out[:, 1] = np.interp(t, s, points[:, 1])
    return out
