"""Reading curve objects (Bezier, poly and NURBS splines) as polylines, and writing Bezier
curve objects, in bulk per spline (``foreach_get``/``foreach_set``, float32).

Bezier splines are tessellated with their handles, ``resolution_u`` steps a segment; poly
splines are taken as they are; NURBS splines by their control polygon (an approximation
noted in the report).
"""

from __future__ import annotations

import bpy
import numpy as np

from ..core import sample_bezier

__all__ = ["FREE", "ink_material", "new_curve_object", "read_curve", "write_bezier_splines"]

FREE = 0  # handle type, as foreach_set takes it


def _bezier_polyline(spline, resolution: int) -> np.ndarray:
    bp = spline.bezier_points
    n = len(bp)
    co, left, right = (np.empty(n * 3, np.float32) for _ in range(3))
    bp.foreach_get("co", co)
    bp.foreach_get("handle_left", left)
    bp.foreach_get("handle_right", right)
    co, left, right = co.reshape(-1, 3), left.reshape(-1, 3), right.reshape(-1, 3)
    if n < 2:
        return co
    # control points knot, right handle, next knot's left handle, next knot, ... round to
    # the first knot again when cyclic
    order = np.arange(n + 1) % n if spline.use_cyclic_u else np.arange(n)
    ctrl = np.empty((3 * (len(order) - 1) + 1, 3))
    ctrl[0::3], ctrl[1::3], ctrl[2::3] = co[order], right[order[:-1]], left[order[1:]]
    return sample_bezier(ctrl, resolution)


def read_curve(obj) -> tuple[list[np.ndarray], list[bool], int]:
    """Polylines (object space) of every spline, whether each is closed, and the number of
    NURBS splines read by their control polygon."""
    polylines, closed, nurbs = [], [], 0
    resolution = max(1, obj.data.resolution_u)
    for spline in obj.data.splines:
        if spline.type == "BEZIER":
            pts = _bezier_polyline(spline, resolution)
        else:
            buf = np.empty(len(spline.points) * 4, np.float32)
            spline.points.foreach_get("co", buf)
            pts = buf.reshape(-1, 4)[:, :3]
            if spline.use_cyclic_u and len(pts) > 2:
                pts = np.concatenate([pts, pts[:1]])
            nurbs += spline.type == "NURBS"
        if len(pts) >= 2:
            polylines.append(pts)
            closed.append(bool(spline.use_cyclic_u))
    return polylines, closed, nurbs


def write_bezier_splines(curve, knots: list[np.ndarray], lefts: list[np.ndarray],
                         rights: list[np.ndarray], cyclic: list[bool],
                         radius: list[np.ndarray] | None = None) -> None:
    """Add one Bezier spline per stroke to a curve datablock, free handles as given."""
    for k, (co, hl, hr) in enumerate(zip(knots, lefts, rights)):
        spline = curve.splines.new("BEZIER")
        spline.bezier_points.add(len(co) - 1)
        bp = spline.bezier_points
        bp.foreach_set("co", np.ascontiguousarray(co, np.float32).ravel())
        bp.foreach_set("handle_left", np.ascontiguousarray(hl, np.float32).ravel())
        bp.foreach_set("handle_right", np.ascontiguousarray(hr, np.float32).ravel())
        free = np.full(len(co), FREE, np.int32)
        bp.foreach_set("handle_left_type", free)
        bp.foreach_set("handle_right_type", free)
        if radius is not None:
            bp.foreach_set("radius", np.ascontiguousarray(radius[k], np.float32))
        spline.use_cyclic_u = bool(cyclic[k])


def new_curve_object(name: str, like, collection) -> bpy.types.Object:
    """An empty 3D Bezier curve object placed like ``like``, linked where it is.

    It renders as tubes: a bevel of depth 1 times each point's radius, so that a point
    written with a Grease Pencil radius (in metres) is drawn that thick."""
    curve = bpy.data.curves.new(name, type="CURVE")
    curve.dimensions = "3D"
    curve.bevel_depth = 1.0
    curve.use_fill_caps = True
    obj = bpy.data.objects.new(name, curve)
    obj.matrix_world = like.matrix_world
    collection.objects.link(obj)
    return obj


def ink_material(source) -> bpy.types.Material:
    """A surface material with the colour of a Grease Pencil material's strokes (curve
    objects render surfaces, which a Grease Pencil material does not describe); made once
    per source material and reused."""
    name = f"{source.name} (curve)" if source is not None else "SketchSimp ink"
    found = bpy.data.materials.get(name)
    if found is not None:
        return found
    mat = bpy.data.materials.new(name)
    style = getattr(source, "grease_pencil", None) if source is not None else None
    colour = tuple(style.color) if style is not None else (0.0, 0.0, 0.0, 1.0)
    mat.diffuse_color = colour
    tree = mat.node_tree
    if tree is None and hasattr(mat, "use_nodes"):
        mat.use_nodes = True
        tree = mat.node_tree
    bsdf = tree.nodes.get("Principled BSDF") if tree is not None else None
    if bsdf is not None:
        bsdf.inputs["Base Color"].default_value = colour
    return mat
