"""Blender glue: reads Grease Pencil strokes into plain numpy data, runs ``core``, writes
the result back. Only this package imports bpy, and only in the modules that talk to
Blender (gp_io, curve_io, run, operators, panel, options): the package itself and its
plain-data modules (drawing, convert) import without Blender, for tests.
``register``/``unregister`` may be called repeatedly (reloading the add-on)."""

from __future__ import annotations

__all__ = ["register", "unregister"]


def _classes() -> tuple:
    from .operators import SKETCHSIMP_OT_simplify
    from .panel import SKETCHSIMP_PT_panel, SketchSimpSettings

    return (SketchSimpSettings, SKETCHSIMP_OT_simplify, SKETCHSIMP_PT_panel)


def register() -> None:
    import bpy

    from .panel import SketchSimpSettings

    unregister()  # registering again (a reload) replaces what is there
    for cls in _classes():
        bpy.utils.register_class(cls)
    bpy.types.Scene.sketchsimp = bpy.props.PointerProperty(type=SketchSimpSettings)


def unregister() -> None:
    import bpy

    from .run import stop_kept_pool, stop_kept_pool_if_idle

    stop_kept_pool()  # a shot's workers, kept for the redo panel
    if bpy.app.timers.is_registered(stop_kept_pool_if_idle):
        bpy.app.timers.unregister(stop_kept_pool_if_idle)
    if hasattr(bpy.types.Scene, "sketchsimp"):
        del bpy.types.Scene.sketchsimp
    for cls in reversed(_classes()):
        if cls.is_registered:
            bpy.utils.unregister_class(cls)
