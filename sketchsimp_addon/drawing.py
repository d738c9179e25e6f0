"""A Grease Pencil drawing as plain numpy data, both ways: what is read of a drawing, and
the strokes to write into one. No bpy here, so that the conversions between these and
core sketches (:mod:`sketchsimp_addon.convert`) run and test without Blender.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["DrawingData", "NewStrokes"]


@dataclass
class DrawingData:
    """The strokes of one drawing: points of stroke k are ``offsets[k]:offsets[k + 1]``."""

    positions: np.ndarray  # (N, 3) float32, layer space
    offsets: np.ndarray  # (S + 1,) int32
    radius: np.ndarray  # (N,) float32
    opacity: np.ndarray  # (N,) float32
    vertex_color: np.ndarray | None  # (N, 4) float32
    material_index: np.ndarray  # (S,) int32
    cyclic: np.ndarray  # (S,) bool

    selected: np.ndarray  # (S,) bool
    curve_type: np.ndarray  # (S,) int8

    @property
    def num_strokes(self) -> int:
        return len(self.offsets) - 1

    def stroke_slices(self) -> list[slice]:
        return [slice(int(a), int(b)) for a, b in zip(self.offsets[:-1], self.offsets[1:])]


@dataclass
class NewStrokes:
    """Strokes to add: Bezier knots with their handles, and per-knot attributes."""

    knots: list[np.ndarray]  # (k, 3) float32 each
    handles_left: list[np.ndarray]
    handles_right: list[np.ndarray]
    radius: list[np.ndarray]
    opacity: list[np.ndarray]
    vertex_color: list[np.ndarray] | None
    material_index: np.ndarray  # (S,) int32
    cyclic: np.ndarray  # (S,) bool

    @classmethod
    def none(cls) -> NewStrokes:
        """No strokes: what an empty keyframe is simplified into."""
        return cls([], [], [], [], [], None, np.zeros(0, np.int32), np.zeros(0, bool))

    @classmethod
    def as_drawn(cls, data: DrawingData) -> NewStrokes:
        """A drawing's strokes as they are, knot for point (handles on the knots: the
        polyline drawn), with their radius, opacity, colour, material and closure: what a
        result layer shows at a keyframe that was not simplified, so that hiding the
        source shows the same there."""
        cut = data.stroke_slices()
        knots = [data.positions[c].astype(np.float32) for c in cut]
        return cls(knots, [k.copy() for k in knots], [k.copy() for k in knots],
                   [data.radius[c] for c in cut], [data.opacity[c] for c in cut],
                   None if data.vertex_color is None else [data.vertex_color[c] for c in cut],
                   data.material_index.astype(np.int32), data.cyclic.astype(bool))
