"""Building Grease Pencil test scenes from the project's sample sketches (needs bpy)."""

from __future__ import annotations

import bpy
import numpy as np
from extension import load_extension  # noqa: F401  (scripts/, re-exported for tests)
from helpers import SAMPLES

from core import read_sketch

GP_DATA = bpy.data.grease_pencils_v3 if hasattr(bpy.data, "grease_pencils_v3") \
    else bpy.data.grease_pencils
SCALE = 0.01  # sample pixels to metres


def clear_scene() -> None:
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    for gp in list(GP_DATA):
        GP_DATA.remove(gp)


def sample_points(name: str) -> list[np.ndarray]:
    """A sample sketch as 3D strokes on the X-Z plane (front view), y = 0."""
    sketch = read_sketch(SAMPLES / f"{name}.scap")
    return [np.stack([s.points[:, 0] * SCALE, np.zeros(len(s)), -s.points[:, 1] * SCALE],
                     axis=1).astype(np.float32) for s in sketch.strokes]


def fill_drawing(drawing, strokes: list[np.ndarray], radius: float = 0.01) -> None:
    if not strokes:
        return
    drawing.add_strokes([len(s) for s in strokes])
    attrs = drawing.attributes
    n = sum(len(s) for s in strokes)
    attrs["position"].data.foreach_set("vector", np.concatenate(strokes).ravel())
    for name, value in (("radius", radius), ("opacity", 0.9)):
        attr = attrs.get(name) or attrs.new(name, "FLOAT", "POINT")
        attr.data.foreach_set("value", np.full(n, value, np.float32))


def make_object(frames: dict[int, str | None], name: str = "Sketch", layer_name: str = "Lines"):
    """A Grease Pencil object with one layer whose keyframes hold the named samples."""
    gp = GP_DATA.new(name)
    ob = bpy.data.objects.new(name, gp)
    bpy.context.scene.collection.objects.link(ob)
    mat = bpy.data.materials.new("Ink")
    bpy.data.materials.create_gpencil_data(mat)
    gp.materials.append(mat)
    layer = gp.layers.new(layer_name, set_active=True)
    for number, sample in frames.items():
        frame = layer.frames.new(number)
        fill_drawing(frame.drawing, sample_points(sample) if sample else [])
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    return ob


def snapshot(drawing) -> dict[str, bytes]:
    """Every attribute buffer of a drawing, as bytes, to prove it did not change."""
    out = {}
    attrs = drawing.attributes
    for attr in attrs:
        n = attrs.domain_size(attr.domain)
        width = {"FLOAT_VECTOR": 3, "FLOAT_COLOR": 4, "BYTE_COLOR": 4}.get(attr.data_type, 1)
        key = {"FLOAT_VECTOR": "vector", "FLOAT_COLOR": "color", "BYTE_COLOR": "color"}.get(
            attr.data_type, "value")
        dtype = {"INT": np.int32, "INT8": np.int8, "BOOLEAN": bool}.get(attr.data_type,
                                                                        np.float32)
        buf = np.empty(n * width, dtype)
        attr.data.foreach_get(key, buf)
        out[attr.name] = buf.tobytes()
    return out


def drawn_strokes(drawing, steps: int = 16) -> list[np.ndarray]:
    """Each stroke of a drawing as points along it: Bezier strokes evaluated from their
    knots and handles, other strokes as their points."""
    attrs = drawing.attributes
    n = attrs.domain_size("POINT")

    def vec(name):
        buf = np.empty(n * 3, np.float32)
        attrs[name].data.foreach_get("vector", buf)
        return buf.reshape(-1, 3)

    p = vec("position")
    bezier = attrs.get("handle_left") is not None
    left, right = (vec("handle_left"), vec("handle_right")) if bezier else (p, p)
    offsets = np.empty(attrs.domain_size("CURVE") + 1, np.int32)
    drawing.curve_offsets.foreach_get("value", offsets)
    cyclic = np.zeros(len(offsets) - 1, bool)
    if attrs.get("cyclic") is not None:
        attrs["cyclic"].data.foreach_get("value", cyclic)
    t = np.linspace(0, 1, steps)[:, None]
    out = []
    for k, (a, b) in enumerate(zip(offsets[:-1], offsets[1:])):
        idx = list(range(a, b))
        pairs = list(zip(idx[:-1], idx[1:])) + ([(idx[-1], idx[0])] if cyclic[k] else [])
        if not bezier or not pairs:
            out.append(p[a:b])
            continue
        out.append(np.concatenate([(1 - t) ** 3 * p[i] + 3 * (1 - t) ** 2 * t * right[i]
                                   + 3 * (1 - t) * t ** 2 * left[j] + t ** 3 * p[j]
                                   for i, j in pairs]))
    return out
