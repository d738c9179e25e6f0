"""The Simplify Sketch operator: the Blender-facing shell around :mod:`.run` (scheduling)
and :mod:`.write`."""

from __future__ import annotations

import time
import traceback

import bpy

from ..core import SketchError
from .options import SimplifyOptions
from .run import (
    KEPT_IDLE,
    StepwiseRun,
    simplify_curve_object,
    simplify_object,
    stop_kept_pool_if_idle,
)
from .write import write_curve_result, write_results

__all__ = ["MODAL_FROM", "SKETCHSIMP_OT_simplify", "scene_range"]

#: from this many drawings on, a run from the interface is modal: Blender stays drawn, the
#: progress bar moves a drawing at a time, Esc cancels (what finished is written)
MODAL_FROM = 2
#: seconds of work per timer tick of a modal run, at least one drawing: short enough for
#: Esc and the progress bar to answer at once
TICK = 0.1


def scene_range(scene) -> tuple[int, int]:
    """The frames the scene plays: its preview range when that is on."""
    if scene.use_preview_range:
        return scene.frame_preview_start, scene.frame_preview_end
    return scene.frame_start, scene.frame_end


class SKETCHSIMP_OT_simplify(SimplifyOptions, bpy.types.Operator):
    """Turn the rough strokes of the active Grease Pencil object into few clean curves"""

    bl_idname = "sketchsimp.simplify"
    bl_label = "Simplify Sketch"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context) -> bool:
        obj = context.active_object
        if obj is None:
            cls.poll_message_set(
                "No active object: select a Grease Pencil object" if not bpy.app.background
                else "No active object: set bpy.context.view_layer.objects.active, or run "
                "scripts/batch_simplify.py for every Grease Pencil object")
            return False
        if obj.type not in ("GREASEPENCIL", "CURVE"):
            cls.poll_message_set(f"'{obj.name}' is neither a Grease Pencil nor a curve object")
            return False
        return True

    def execute(self, context):
        try:
            return self._execute(context)
        except Exception as exc:  # the operator boundary: a report, not a traceback dialog
            traceback.print_exc()
            self.report({"ERROR"}, f"Simplify Sketch failed: {type(exc).__name__}: {exc}")
            return {"CANCELLED"}

    def invoke(self, context, event):
        """Many drawings from the interface run modal; one drawing, the redo panel, scripts
        and background mode run :meth:`execute` at once."""
        obj = context.active_object
        if (context.window is None or obj.type != "GREASEPENCIL"
                or self.scope not in ("ALL", "RANGE")):
            return self.execute(context)
        try:
            params = self.params()
            run = StepwiseRun(obj, self, params, context.scene.frame_current,
                              scene_range(context.scene) if self.scope == "RANGE" else None)
        except SketchError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        if run.total < MODAL_FROM:
            return self.execute(context)
        self._run = run
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.01, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, run.total)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            return self._end(context)
        if event.type != "TIMER":
            return {"RUNNING_MODAL"}  # nothing else touches the drawings meanwhile
        run = self._run
        try:
            deadline = time.perf_counter() + TICK
            run.step(TICK)
            while not run.done and time.perf_counter() < deadline:
                run.step(max(0.0, deadline - time.perf_counter()))
        except Exception as exc:  # the operator boundary, as in execute
            traceback.print_exc()
            self.report({"ERROR"}, f"Simplify Sketch failed: {type(exc).__name__}: {exc}")
            return self._end(context, failed=True)
        context.window_manager.progress_update(run.finished)
        context.workspace.status_text_set(
            f"Simplify Sketch: {run.finished} of {run.total} drawings (Esc to cancel)")
        return self._end(context) if run.done else {"RUNNING_MODAL"}

    def _end(self, context, failed: bool = False):
        """Stop the modal run; write what finished (all of it, unless cancelled)."""
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        obj, run = context.active_object, self._run
        results = [] if failed else run.finish()
        if not any(r.chosen for r in results):
            if not failed:
                self.report({"WARNING"}, "Simplify Sketch cancelled: nothing was changed")
            return {"CANCELLED"}
        write_results(obj, self, results, context)
        self._finish(context, run.report)
        return {"FINISHED"}

    def _execute(self, context):
        obj = context.active_object
        try:
            params = self.params()
        except SketchError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        if obj.type == "CURVE":
            return self._execute_curve(context, obj, params)
        wm = context.window_manager
        wm.progress_begin(0.0, 1.0)
        try:
            report, results = simplify_object(obj, self, params, context.scene.frame_current,
                                              progress=wm.progress_update,
                                              frame_range=scene_range(context.scene)
                                              if self.scope == "RANGE" else None)
        finally:
            wm.progress_end()
        if not results:
            why = "; ".join(report.skipped) if report.skipped else "no strokes found"
            self.report({"ERROR"}, f"Nothing to simplify on '{obj.name}': {why}")
            return {"CANCELLED"}
        write_results(obj, self, results, context)
        self._finish(context, report)
        return {"FINISHED"}

    def _execute_curve(self, context, obj, params):
        report, new = simplify_curve_object(obj, params)
        if new is None:
            self.report({"ERROR"}, f"Nothing to simplify on '{obj.name}': "
                        + "; ".join(report.skipped))
            return {"CANCELLED"}
        write_curve_result(obj, self, new, context)
        self._finish(context, report)
        return {"FINISHED"}

    def _finish(self, context, report) -> None:
        if not bpy.app.timers.is_registered(stop_kept_pool_if_idle):  # a shot's pool
            bpy.app.timers.register(stop_kept_pool_if_idle, first_interval=KEPT_IDLE,
                                    persistent=True)
        settings = getattr(context.scene, "sketchsimp", None)
        if settings is not None:
            settings.last_run = report.message()
        self.report({"WARNING"} if report.skipped or report.notes else {"INFO"},
                    report.message())

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "epsilon", slider=True)
        for name in ("scope", "layers", "output", "hide_source", "stable", "fill_regions",
                     "as_curve"):
            layout.prop(self, name)
        box = layout.box()
        box.label(text="Advanced")
        for name in ("alpha", "samples", "angle", "corner_angle", "smoothing"):
            box.prop(self, name)
