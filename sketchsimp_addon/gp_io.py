"""Reading and writing Grease Pencil v3 drawings in bulk, as plain numpy arrays
(:mod:`sketchsimp_addon.drawing`).

Every attribute moves with one ``foreach_get``/``foreach_set`` of the exact dtype Blender
stores (float32, int32, int8, bool): no per-point Python. Attributes a drawing lacks read
as Blender's own defaults (radius 0.01, opacity 1, material 0, open, selected); written
strokes always get radius and opacity, since new attributes start at zero (invisible).
"""

from __future__ import annotations

import bpy
import numpy as np

from .drawing import DrawingData, NewStrokes

__all__ = ["DEFAULTS", "FREE_HANDLE", "grease_pencil_data", "read_drawing", "write_strokes"]

#: Blender's defaults for a stroke attribute the drawing does not have
DEFAULTS = {"radius": 0.01, "opacity": 1.0, "material_index": 0, "cyclic": False}
BEZIER, POLY = 2, 1
FREE_HANDLE = 0


def grease_pencil_data():
    """The Grease Pencil v3 ID collection: ``grease_pencils_v3`` on 4.3-4.5, else 5.0+."""
    return bpy.data.grease_pencils_v3 if hasattr(bpy.data, "grease_pencils_v3") \
        else bpy.data.grease_pencils


def _get(attrs, name: str, n: int, dtype, key: str, width: int = 1):
    attr = attrs.get(name)
    if attr is None:
        return None
    out = np.empty(n * width, dtype=dtype)
    attr.data.foreach_get(key, out)
    return out.reshape(n, width) if width > 1 else out


def read_drawing(drawing) -> DrawingData:
    """All strokes of a drawing (``GreasePencilDrawing``), with defaults filled in."""
    attrs = drawing.attributes
    n_pts, n_strokes = attrs.domain_size("POINT"), attrs.domain_size("CURVE")
    offsets = np.zeros(n_strokes + 1, dtype=np.int32)
    if n_strokes:
        drawing.curve_offsets.foreach_get("value", offsets)
    positions = _get(attrs, "position", n_pts, np.float32, "vector", 3)
    if positions is None:
        positions = np.zeros((0, 3), np.float32)

    def point(name, dtype=np.float32):
        v = _get(attrs, name, n_pts, dtype, "value")
        return np.full(n_pts, DEFAULTS[name], dtype) if v is None else v

    def curve(name, dtype):
        v = _get(attrs, name, n_strokes, dtype, "value")
        return np.full(n_strokes, DEFAULTS.get(name, 0), dtype) if v is None else v

    selection = attrs.get(".selection")
    if selection is None:
        selected = np.ones(n_strokes, dtype=bool)
    elif selection.domain == "CURVE":
        selected = _get(attrs, ".selection", n_strokes, bool, "value")
    else:
        per_point = _get(attrs, ".selection", n_pts, bool, "value")
        selected = np.logical_or.reduceat(per_point, offsets[:-1]) if n_pts else \
            np.zeros(n_strokes, bool)
    return DrawingData(
        positions=positions.reshape(-1, 3), offsets=offsets, radius=point("radius"),
        opacity=point("opacity"),
        vertex_color=_get(attrs, "vertex_color", n_pts, np.float32, "color", 4),
        material_index=curve("material_index", np.int32), cyclic=curve("cyclic", bool),
        selected=selected, curve_type=_get(attrs, "curve_type", n_strokes, np.int8, "value")
        if attrs.get("curve_type") is not None else np.full(n_strokes, POLY, np.int8),
    )


def _ensure(attrs, name: str, kind: str, domain: str):
    attr = attrs.get(name)
    return attr if attr is not None else attrs.new(name, kind, domain)


def write_strokes(drawing, new: NewStrokes) -> None:
    """Append Bezier strokes to a drawing, every attribute written in bulk."""
    if not new.knots:
        return
    first = drawing.attributes.domain_size("CURVE")
    drawing.add_strokes([len(k) for k in new.knots])
    attrs = drawing.attributes
    n_pts = attrs.domain_size("POINT")
    n_strokes = attrs.domain_size("CURVE")
    offsets = np.empty(n_strokes + 1, dtype=np.int32)
    drawing.curve_offsets.foreach_get("value", offsets)
    start = int(offsets[first])
    mine = slice(start, n_pts)
    stroke_indices = list(range(first, n_strokes))
    drawing.set_types(type="BEZIER", indices=stroke_indices)

    def put_points(name, kind, key, values, width=1, dtype=np.float32):
        attr = _ensure(attrs, name, kind, "POINT")
        full = np.empty(n_pts * width, dtype=dtype)
        attr.data.foreach_get(key, full)
        full = full.reshape(n_pts, width) if width > 1 else full
        full[mine] = values
        attr.data.foreach_set(key, full.ravel())

    put_points("position", "FLOAT_VECTOR", "vector", np.concatenate(new.knots), 3)
    put_points("handle_left", "FLOAT_VECTOR", "vector", np.concatenate(new.handles_left), 3)
    put_points("handle_right", "FLOAT_VECTOR", "vector", np.concatenate(new.handles_right), 3)
    free = np.full(n_pts - start, FREE_HANDLE, np.int8)
    put_points("handle_type_left", "INT8", "value", free, dtype=np.int8)
    put_points("handle_type_right", "INT8", "value", free, dtype=np.int8)
    put_points("radius", "FLOAT", "value", np.concatenate(new.radius))
    put_points("opacity", "FLOAT", "value", np.concatenate(new.opacity))
    if new.vertex_color is not None:
        put_points("vertex_color", "FLOAT_COLOR", "color", np.concatenate(new.vertex_color), 4)

    def put_curves(name, kind, values, dtype):
        attr = _ensure(attrs, name, kind, "CURVE")
        full = np.empty(n_strokes, dtype=dtype)
        attr.data.foreach_get("value", full)
        full[first:] = values
        attr.data.foreach_set("value", full)

    put_curves("material_index", "INT", new.material_index, np.int32)
    put_curves("cyclic", "BOOLEAN", new.cyclic, bool)
    # where the drawing keeps a selection, the new strokes are selected (they replace, or
    # stand beside, what was selected); with none, every stroke counts as selected anyway
    selection = attrs.get(".selection")
    if selection is not None:
        size, mine_of = ((n_strokes, slice(first, n_strokes)) if selection.domain == "CURVE"
                         else (n_pts, mine))
        full = np.empty(size, dtype=bool)
        selection.data.foreach_get("value", full)
        full[mine_of] = True
        selection.data.foreach_set("value", full)
    drawing.tag_positions_changed()
