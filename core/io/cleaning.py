"""Cleaning raw strokes and normalising a sketch to a unit bounding-box diagonal."""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..sketch import Sketch, SketchError, Stroke

__all__ = ["clean_sketch", "clean_stroke", "CleaningReport", "Normalisation", "normalised_strokes"]


@dataclass
class CleaningReport:
    """What :func:`clean_sketch` removed."""

    strokes_in: int
    strokes_out: int
    nonfinite_points: int
    duplicate_points: int
    degenerate_strokes: int

    def as_dict(self) -> dict[str, int]:
        return asdict(self)


def clean_stroke(stroke: Stroke) -> tuple[Stroke | None, int, int]:
    """Drop non-finite points and consecutive duplicates.

    Returns the cleaned stroke (None when fewer than 2 distinct points remain), the number
    of non-finite points and the number of duplicate points removed.
    """
    pts = stroke.points
    finite = np.isfinite(pts).all(axis=1)
    keep = np.flatnonzero(finite)
    kept = pts[keep]
    distinct = np.ones(len(kept), dtype=bool)
    distinct[1:] = (kept[1:] != kept[:-1]).any(axis=1)
    keep = keep[distinct]
    nonfinite = int(len(pts) - finite.sum())
    duplicates = int(len(kept) - distinct.sum())
    if len(keep) < 2:
        return None, nonfinite, duplicates
    if nonfinite == 0 and duplicates == 0:
        return stroke, 0, 0
    return stroke.with_points(pts[keep], keep), nonfinite, duplicates


def clean_sketch(sketch: Sketch) -> tuple[Sketch, CleaningReport]:
    """Remove what cannot be drawn; raise :class:`SketchError` if nothing drawable is left."""
    if not isinstance(sketch, Sketch):
        raise SketchError(f"expected a Sketch, got {type(sketch).__name__}")
    if len(sketch.strokes) == 0:
        raise SketchError("the sketch has no strokes")
    out: list[Stroke] = []
    nonfinite = duplicates = degenerate = 0
    for stroke in sketch.strokes:
        cleaned, nf, dup = clean_stroke(stroke)
        nonfinite += nf
        duplicates += dup
        if cleaned is None:
            degenerate += 1
        else:
            out.append(cleaned)
    if not out:
        raise SketchError(
            f"none of the {len(sketch.strokes)} strokes has two distinct finite points"
        )
    report = CleaningReport(len(sketch.strokes), len(out), nonfinite, duplicates, degenerate)
    return Sketch(out, sketch.width, sketch.height), report


#: extents whose squares still are normal floating-point numbers
MIN_EXTENT, MAX_EXTENT = 1e-150, 1e150


@dataclass(frozen=True)
class Normalisation:
    """Maps drawing coordinates to a frame whose bounding box has diagonal 1 and back."""

    origin: tuple[float, float]
    scale: float

    @classmethod
    def of(cls, sketch: Sketch) -> Normalisation:
        x0, y0, x1, y1 = sketch.bounds()
        diag = float(np.hypot(x1 - x0, y1 - y0))
        if not np.isfinite(diag) or diag <= 0.0:
            raise SketchError("the sketch has zero extent: every point is the same")
        if not MIN_EXTENT <= diag <= MAX_EXTENT:
            raise SketchError(f"the sketch's extent {diag:.3g} is outside {MIN_EXTENT:.0e} to "
                              f"{MAX_EXTENT:.0e}, where distances cannot be measured")
        return cls((x0, y0), diag)

    def to_unit(self, points: np.ndarray) -> np.ndarray:
        return (points - np.asarray(self.origin)) / self.scale

    def from_unit(self, points: np.ndarray) -> np.ndarray:
        return points * self.scale + np.asarray(self.origin)


def normalised_strokes(sketch: Sketch) -> tuple[list[np.ndarray], Normalisation]:
    """The stroke polylines of a cleaned sketch in the unit-diagonal frame."""
    norm = Normalisation.of(sketch)
    return [norm.to_unit(s.points) for s in sketch.strokes], norm
