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


def split_coordinates(geoms: np.ndarray) -> list[np.ndarray]:
    """The coordinates of each geometry, as a list of (k, 2) arrays."""
    coords, index = shapely.get_coordinates(geoms, return_index=True)
    cuts = np.flatnonzero(np.diff(index)) + 1
    return np.split(coords, cuts) if len(coords) else []


def arc_lengths(points: np.ndarray) -> np.ndarray:
    """Cumulative arc length at each point, starting at 0."""
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))])


def resample_polyline(points: np.ndarray, spacing: float) -> np.ndarray:
    """Points evenly spaced by arc length (at most ``spacing`` apart), ends kept; a closed
    polyline keeps at least four, so that it stays a loop however short."""
    s = arc_lengths(points)
    closed = len(points) > 2 and bool((points[0] == points[-1]).all())
    n = max(4 if closed else 2, int(np.ceil(s[-1] / spacing)) + 1)
    t = np.linspace(0.0, s[-1], n)
    return np.stack([np.interp(t, s, points[:, 0]), np.interp(t, s, points[:, 1])], axis=1)


def unit_tangents(points: np.ndarray) -> np.ndarray:
    """Unit tangent at each point (central differences, one-sided at the ends)."""
    d = np.gradient(points, axis=0) if len(points) > 2 else np.repeat(
        points[1:] - points[:1], len(points), axis=0)
    norm = np.hypot(d[:, 0], d[:, 1])
    return d / np.where(norm > 0, norm, 1.0)[:, None]
