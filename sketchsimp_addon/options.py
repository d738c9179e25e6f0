"""The options shared by the operator (its redo panel) and the sidebar panel's settings."""

from __future__ import annotations

from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty

from ..core import EPSILON_SOFT_MAX, SimplifyParams

__all__ = ["DEFAULTS", "LAYER_ITEMS", "OUTPUT_ITEMS", "SCOPE_ITEMS",
           "SimplifyOptions"]

DEFAULTS = SimplifyParams()

SCOPE_ITEMS = [
    ("CURRENT", "Current Frame", "Simplify the drawing shown at the current frame"),
    ("ALL", "All Keyframes", "Simplify every keyframe's drawing (shared drawings once)"),
    ("RANGE", "Frame Range", "Simplify the drawings shown in the scene's frame range (the "
     "preview range when it is on): its keyframes and the one showing at its start"),
    ("SELECTED", "Selected Strokes", "Simplify only the selected strokes of the current frame"),
]
LAYER_ITEMS = [
    ("ACTIVE", "Active Layer", "Only the active layer"),
    ("VISIBLE", "Visible Layers", "Every visible, unlocked layer"),
]
OUTPUT_ITEMS = [
    ("LAYER", "New Layer", "Write the result to a new layer above each source layer"),
    ("OBJECT", "New Object", "Write the result to a new Grease Pencil object"),
    ("REPLACE", "Replace", "Replace the source strokes in place (undo restores them)"),
]

class SimplifyOptions:
    """Annotations mixed into both the operator and the scene settings."""

    epsilon: FloatProperty(
        name="Epsilon", default=DEFAULTS.epsilon, min=0.0, soft_max=EPSILON_SOFT_MAX,
        precision=3, step=0.1, description="How far to simplify: the largest change of "
        "shape a merge may make (0 keeps every stroke; 0.01 to 0.03 suits most sketches)")
    scope: EnumProperty(name="Scope", items=SCOPE_ITEMS, default="CURRENT",
                        description="Which drawings and strokes to simplify")
    layers: EnumProperty(name="Layers", items=LAYER_ITEMS, default="ACTIVE",
                         description="Which layers to simplify")
    output: EnumProperty(name="Output", items=OUTPUT_ITEMS, default="LAYER",
                         description="Where the simplified strokes go")
    hide_source: BoolProperty(name="Hide Source", default=True,
                              description="Hide each source layer once its result is written "
                              "to a new layer or object")
    stable: BoolProperty(
        name="Stable Across Frames", default=True,
        description="With All Keyframes or Frame Range: hold each keyframe's lines to the "
        "keyframe's before it where the drawing did not change (within the bundle width), "
        "so that slightly redrawn frames do not boil, and carry them along where the "
        "drawing moved or turned")
    fill_regions: BoolProperty(
        name="Fill Regions", default=False,
        description="Also write the regions the clean lines close as fills, on a layer "
        "under the lines (with the object's first fill material, or a new one); holes stay "
        "holes. Not for As Curve Object")
    as_curve: BoolProperty(name="As Curve Object", default=False,
                           description="Write the result as Bezier curve objects instead of "
                           "strokes: one per layer, or for a layer of several keyframes one "
                           "per drawing, each shown only on its drawing's frames")
    alpha: FloatProperty(
        name="Bundle Width", default=0.0, min=0.0, max=0.2, precision=3,
        description="Width of a bundle of rough strokes as a fraction of the drawing's size "
        "(a stray mark far away on the layer does not count): strokes closer than this may "
        "merge (alpha). 0: auto, measured from the ink (from 0.006 where strokes are dense, "
        "half the paper's 0.012, up to 0.015 where they lie far apart for the drawing's "
        "size, up to 0.03 where the result that wide still keeps all the ink)")
    samples: IntProperty(name="Shape Samples", default=DEFAULTS.samples, min=8, max=2048,
                         description="Points used to compare shapes (Fourier descriptor N); "
                         "more is finer and slower")
    angle: FloatProperty(name="Merge Angle", default=DEFAULTS.angle, min=0.0, max=90.0,
                         description="Largest angle, in degrees, between strokes that may merge")
    corner_angle: FloatProperty(name="Corner Angle", default=DEFAULTS.corner_angle, min=5.0,
                                max=180.0, description="Turns sharper than this, in degrees, "
                                "stay sharp corners of the output curves")
    smoothing: FloatProperty(name="Smoothing", default=DEFAULTS.smoothing, min=0.0, max=4.0,
                             description="Smooth each output line between its corners over "
                             "this many bundle widths, so that it shows no steps (0: none)")

    def params(self) -> SimplifyParams:
        return SimplifyParams(epsilon=self.epsilon, alpha=self.alpha or "auto",
                              samples=self.samples - self.samples % 2, angle=self.angle,
                              corner_angle=self.corner_angle, smoothing=self.smoothing)
