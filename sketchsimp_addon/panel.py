"""The SketchSimp tab of the 3D viewport's sidebar and the scene settings it shows."""

from __future__ import annotations

import bpy
from bpy.props import StringProperty

from .options import SimplifyOptions

__all__ = ["OPTION_NAMES", "SKETCHSIMP_PT_panel", "SketchSimpSettings"]

OPTION_NAMES = ("epsilon", "scope", "layers", "output", "hide_source", "stable", "fill_regions",
                "as_curve", "alpha", "samples", "angle",
                "corner_angle", "smoothing")


class SketchSimpSettings(SimplifyOptions, bpy.types.PropertyGroup):
    """The panel's settings, kept with the scene, and the last run's numbers."""

    last_run: StringProperty(name="Last Run", default="",
                             description="What the last Simplify Sketch run did")


class SKETCHSIMP_PT_panel(bpy.types.Panel):
    bl_label = "SketchSimp"
    bl_idname = "SKETCHSIMP_PT_panel"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "SketchSimp"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.sketchsimp
        layout.prop(settings, "epsilon", slider=True)
        layout.prop(settings, "scope")
        layout.prop(settings, "layers")
        layout.prop(settings, "output")
        layout.prop(settings, "hide_source")
        layout.prop(settings, "stable")
        layout.prop(settings, "fill_regions")
        layout.prop(settings, "as_curve")
        op = layout.operator("sketchsimp.simplify", icon="MOD_SIMPLIFY")
        for name in OPTION_NAMES:
            setattr(op, name, getattr(settings, name))
        if settings.last_run:
            layout.label(text=settings.last_run)
