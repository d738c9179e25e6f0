"""How good a simplification is: measures on drawings given as lists of polylines.

All distances are in the drawings' own units. Drawings are compared through points
sampled along them every ``spacing`` units, so that long segments count by their length.

* coverage(ink, output, tol): fraction of the input ink within ``tol`` of the output;
* fidelity(output, ink): mean distance of the output to the nearest input ink;
* precision_recall_f(output, reference, tol): the output's share within ``tol`` of the
  reference (precision), the reference's share within ``tol`` of the output (recall), F1;
* chamfer(a, b): the symmetric Chamfer distance, the mean of both mean nearest distances.
"""

from __future__ import annotations

import numpy as np
import shapely

from core.arrays.geometry import lines_from
from core.arrays.polylines import resample_polyline

__all__ = [
    "chamfer", "coverage", "fidelity", "nearest_distances", "precision_recall_f", "sample_points",
]


def sample_points(polylines: list[np.ndarray], spacing: float) -> np.ndarray:
    pieces = [resample_polyline(p, spacing) for p in polylines if len(p) >= 2]
    return np.concatenate(pieces) if pieces else np.empty((0, 2))


def nearest_distances(points: np.ndarray, polylines: list[np.ndarray]) -> np.ndarray:
    """Distance from each point to the nearest of the polylines (inf when there are none)."""
    lines = [p for p in polylines if len(p) >= 2]
    if not lines:
        return np.full(len(points), np.inf)
    geoms = lines_from(lines)
    pts = shapely.points(points)
    idx = shapely.STRtree(geoms).query_nearest(pts, all_matches=False)[1]
    return shapely.distance(pts, geoms[idx])


def coverage(ink: list[np.ndarray], output: list[np.ndarray], tol: float,
             spacing: float = 1.0) -> float:
    pts = sample_points(ink, spacing)
    return float((nearest_distances(pts, output) <= tol).mean()) if len(pts) else 1.0


def fidelity(output: list[np.ndarray], ink: list[np.ndarray], spacing: float = 1.0) -> float:
    pts = sample_points(output, spacing)
    return float(nearest_distances(pts, ink).mean()) if len(pts) else 0.0


def precision_recall_f(output: list[np.ndarray], reference: list[np.ndarray], tol: float,
                       spacing: float = 1.0) -> tuple[float, float, float]:
    out_pts, ref_pts = sample_points(output, spacing), sample_points(reference, spacing)
    precision = float((nearest_distances(out_pts, reference) <= tol).mean()) if len(
        out_pts) else 0.0
    recall = float((nearest_distances(ref_pts, output) <= tol).mean()) if len(ref_pts) else 0.0
    f = 2 * precision * recall / (precision + recall) if precision + recall > 0 else 0.0
    return precision, recall, f


def chamfer(a: list[np.ndarray], b: list[np.ndarray], spacing: float = 1.0) -> float:
    pa, pb = sample_points(a, spacing), sample_points(b, spacing)
    return float(0.5 * (nearest_distances(pa, b).mean() + nearest_distances(pb, a).mean()))
