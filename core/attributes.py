"""Carrying width, pressure and style from the input strokes over to output strokes.

Each output point takes the values of the nearest point of the nearest input stroke; the
stroke's style is the most common style among the input strokes nearest to its points.
"""

from __future__ import annotations

from collections import Counter

import numpy as np
import shapely

from .geometry import lines_from
from .sketch import Stroke


class NearestInk:
    """Nearest-stroke look-ups over the input strokes (unit frame)."""

    def __init__(self, strokes: list[Stroke], unit_points: list[np.ndarray]) -> None:
        self.strokes = strokes
        self.points = unit_points
        self.tree = shapely.STRtree(lines_from(unit_points))

    def transfer(self, points: np.ndarray) -> tuple[np.ndarray | None, np.ndarray | None,
                                                     str | None, tuple[int, ...]]:
        """Width and pressure per point, style, and ids of the input strokes used."""
        nearest = self.tree.query_nearest(shapely.points(points), all_matches=False)[1]
        ids = tuple(sorted({self.strokes[k].source_id if self.strokes[k].source_id is not None
                            else int(k) for k in nearest.tolist()}))
        width = self._per_point("width", nearest, points)
        pressure = self._per_point("pressure", nearest, points)
        styles = Counter(self.strokes[k].style for k in nearest.tolist()
                         if self.strokes[k].style is not None)
        style = styles.most_common(1)[0][0] if styles else None
        return width, pressure, style, ids

    def _per_point(self, name: str, nearest: np.ndarray, points: np.ndarray) -> np.ndarray | None:
        if all(getattr(self.strokes[k], name) is None for k in set(nearest.tolist())):
            return None
        out = np.empty(len(points))
        for k in np.unique(nearest).tolist():
            rows = np.flatnonzero(nearest == k)
            values = getattr(self.strokes[k], name)
            if values is None:
                out[rows] = np.nan
                continue
            src = self.points[k]
            d = np.hypot(*(points[rows][:, None, :] - src[None, :, :]).transpose(2, 0, 1))
            out[rows] = values[d.argmin(axis=1)]
        if np.isnan(out).all():
            return None
        return np.where(np.isnan(out), np.nanmean(out), out)
