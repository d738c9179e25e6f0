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


def polyline_length(points: np.ndarray) -> float:
    return float(np.hypot(*np.diff(points, axis=0).T).sum())
