"""The Simplify Sketch operator: the Blender-facing shell around :mod:`.run`."""

from __future__ import annotations

import bpy

from ..core.sketch import SketchError
from .options import SimplifyOptions
from .run import simplify_object, write_results


class SKETCHSIMP_OT_simplify(SimplifyOptions, bpy.types.Operator):
    """Turn the rough strokes of the active Grease Pencil object into few clean curves"""

    bl_idname = "sketchsimp.simplify"
    bl_label = "Simplify Sketch"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context) -> bool:
        obj = context.active_object
        if obj is None:
            cls.poll_message_set("No active object: select a Grease Pencil object")
            return False
        if obj.type != "GREASEPENCIL":
            cls.poll_message_set(f"'{obj.name}' is not a Grease Pencil object")
            return False
        return True

    def execute(self, context):
        obj = context.active_object
        try:
            params = self.params()
        except SketchError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        wm = context.window_manager
        wm.progress_begin(0, max(1, len(obj.data.layers)))
        try:
            report, results = simplify_object(obj, self, params, context.scene.frame_current,
                                              progress=wm.progress_update)
        finally:
            wm.progress_end()
        if not results:
            why = "; ".join(report.skipped) if report.skipped else "no strokes found"
            self.report({"ERROR"}, f"Nothing to simplify on '{obj.name}': {why}")
            return {"CANCELLED"}
        write_results(obj, self, results, context)
        settings = getattr(context.scene, "sketchsimp", None)
        if settings is not None:
            settings.last_run = report.message()
        self.report({"WARNING"} if report.skipped else {"INFO"}, report.message())
        return {"FINISHED"}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "epsilon", slider=True)
        for name in ("scope", "layers", "output", "hide_source"):
            layout.prop(self, name)
        box = layout.box()
        box.label(text="Advanced")
        for name in ("alpha", "samples", "angle"):
            box.prop(self, name)
