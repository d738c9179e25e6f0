"""Plain data for a sketch: strokes as numpy arrays, nothing else.

A :class:`Stroke` is an ``(n, 2)`` float64 polyline with optional per-point width and
pressure, an optional style (a colour or material name), the id of the input stroke it came
from and an optional cluster id (the intended curve it belongs to, where a data set says so).
Output strokes may also carry the cubic Bezier control points they were fitted with.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

__all__ = ["Region", "Sketch", "SketchError", "Stroke"]


class SketchError(ValueError):
    """Input that cannot be a sketch, or parameters that cannot apply to one."""


def _as_points(points: object) -> np.ndarray:
    try:
        arr = np.asarray(points)
    except (TypeError, ValueError) as exc:  # ragged nested lists
        raise SketchError(f"stroke points are not an array of numbers: {exc}") from None
    if arr.dtype.kind not in "iuf":
        raise SketchError(f"stroke points must be real numbers, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise SketchError(f"stroke points must have shape (n, 2), got {arr.shape}")
    return np.ascontiguousarray(arr, dtype=np.float64)


def _as_per_point(values: object, n: int, name: str) -> np.ndarray | None:
    if values is None:
        return None
    arr = np.asarray(values)
    if arr.dtype.kind not in "iuf":
        raise SketchError(f"stroke {name} must be real numbers, got dtype {arr.dtype}")
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise SketchError(f"stroke {name} must have one value per point ({n}), got {arr.shape}")
    return np.ascontiguousarray(arr, dtype=np.float64)


@dataclass(eq=False)
class Stroke:
    """One polyline of a sketch.

    ``points`` is (n, 2) float64. ``width`` and ``pressure`` are optional (n,) arrays.
    ``bezier`` holds (3k + 1, 2) cubic Bezier control points when the stroke was fitted;
    ``points`` is then its sampled polyline, and ``sources`` names the input strokes
    it was made from.
    """

    points: np.ndarray
    width: np.ndarray | None = None
    pressure: np.ndarray | None = None
    style: str | None = None
    source_id: int | None = None
    cluster: int | None = None
    bezier: np.ndarray | None = None
    closed: bool = False
    sources: tuple[int, ...] = ()  # ids of the input strokes an output stroke came from

    def __post_init__(self) -> None:
        self.points = _as_points(self.points)
        n = len(self.points)
        self.width = _as_per_point(self.width, n, "width")
        self.pressure = _as_per_point(self.pressure, n, "pressure")
        if self.bezier is not None:
            self.bezier = _as_points(self.bezier)
            if (len(self.bezier) - 1) % 3 or len(self.bezier) < 4:
                raise SketchError(
                    f"Bezier control points must number 3k + 1 (k >= 1), got {len(self.bezier)}"
                )

    def __len__(self) -> int:
        return len(self.points)

    def with_points(self, points: np.ndarray, keep: np.ndarray | None = None) -> Stroke:
        """A copy with new points; per-point attributes are indexed by ``keep`` if given."""
        pick = (lambda a: None if a is None else a[keep]) if keep is not None else (lambda a: a)
        return replace(self, points=points, width=pick(self.width),
                       pressure=pick(self.pressure), bezier=None)


@dataclass(eq=False)
class Sketch:
    """A list of strokes and the canvas they were drawn on (``width``, ``height``; optional)."""

    strokes: list[Stroke] = field(default_factory=list)
    width: float | None = None
    height: float | None = None

    def __post_init__(self) -> None:
        strokes = list(self.strokes)
        for i, s in enumerate(strokes):
            if not isinstance(s, Stroke):
                strokes[i] = Stroke(s)
        self.strokes = strokes

    def __len__(self) -> int:
        return len(self.strokes)

    @property
    def num_points(self) -> int:
        return sum(len(s) for s in self.strokes)

    def all_points(self) -> np.ndarray:
        """Every point of every stroke, stacked: (total, 2)."""
        if not self.strokes:
            return np.empty((0, 2))
        return np.concatenate([s.points for s in self.strokes])

    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of the finite points."""
        pts = self.all_points()
        pts = pts[np.isfinite(pts).all(axis=1)]
        if len(pts) == 0:
            raise SketchError("the sketch has no finite points")
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    def diagonal(self) -> float:
        """Length of the bounding-box diagonal, the paper's D."""
        x0, y0, x1, y1 = self.bounds()
        return float(np.hypot(x1 - x0, y1 - y0))


@dataclass(frozen=True)
class Region:
    """A closed region of a drawing, for a fill: its outline and its holes, each an
    ``(n, 2)`` ring (first point not repeated)."""

    outline: np.ndarray
    holes: tuple[np.ndarray, ...] = ()
