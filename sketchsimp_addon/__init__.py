"""Blender glue: reads Grease Pencil strokes into plain numpy data, runs ``core``, writes
the result back. Only this package imports bpy; ``register``/``unregister`` may be called
repeatedly (reloading the add-on)."""

from __future__ import annotations

import bpy

from .operators import SKETCHSIMP_OT_simplify
from .panel import SKETCHSIMP_PT_panel, SketchSimpSettings

CLASSES = (SketchSimpSettings, SKETCHSIMP_OT_simplify, SKETCHSIMP_PT_panel)


def register() -> None:
    unregister()  # registering again (a reload) replaces what is there
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.sketchsimp = bpy.props.PointerProperty(type=SketchSimpSettings)


def unregister() -> None:
    if hasattr(bpy.types.Scene, "sketchsimp"):
        del bpy.types.Scene.sketchsimp
    for cls in reversed(CLASSES):
        if cls.is_registered:
            bpy.utils.unregister_class(cls)
