"""Writing: the results of a run as new layers, a new object, strokes in place, or curve
objects (:func:`write_results`), placed, parented and drawn as their sources are."""

from __future__ import annotations

import bpy

from .curve_io import ink_material, new_curve_object, write_bezier_splines
from .drawing import NewStrokes
from .gp_io import grease_pencil_data, read_drawing, write_strokes
from .records import DrawingResult

__all__ = [
    "as_drawn_besides", "key_visibility", "visible_spans", "write_curves",
    "earlier_result", "FILL_MATERIAL", "fill_materials", "HOLE_MATERIAL", "keep_in_view",
    "layer_to_world", "LOOK", "match_parent", "new_layer_like", "place_above", "result_name",
    "write_curve_result", "write_fills", "write_frames", "write_results",
]


def write_curve_result(obj, options, new: NewStrokes, context):
    """Curve input: replace its splines, or write a new curve object beside it."""
    if options.output == "REPLACE":
        obj.data.splines.clear()
        target = obj
    else:
        target = new_curve_object(obj.name + " simplified", obj, context.collection)
        # drawn as the source is: its bevel and materials (the radius below is 1, Blender's
        # default, the multiplier a curve's own bevel is drawn with)
        target.data.bevel_depth = obj.data.bevel_depth
        target.data.bevel_resolution = obj.data.bevel_resolution
        for mat in obj.data.materials:
            target.data.materials.append(mat)
        if options.hide_source:
            obj.hide_set(True)
    write_bezier_splines(target.data, new.knots, new.handles_left, new.handles_right,
                         list(new.cyclic))
    return target


#: what a new layer takes from its source layer for the strokes to look the same
LOOK = ("opacity", "blend_mode", "tint_color", "tint_factor", "use_lights", "radius_offset",
        "pass_index", "viewlayer_render", "use_masks", "channel_color")
#: names of the materials made for fills: the fill itself, and the holdout cutting holes
FILL_MATERIAL, HOLE_MATERIAL = "SketchSimp Fill", "SketchSimp Hole"


def fill_materials(obj) -> tuple[int, int]:
    """The material slots of the object for fills and for their holes: the first of its
    materials that fills (not a holdout), or a new light grey fill; and a holdout fill,
    made once. Added to the object's materials where missing."""
    mats = obj.data.materials

    def slot(found) -> int:
        for k, mat in enumerate(mats):
            if mat == found:
                return k
        mats.append(found)
        return len(mats) - 1

    def gp_material(name: str, holdout: bool, colour=(0.8, 0.8, 0.8, 1.0)):
        mat = bpy.data.materials.get(name)
        if mat is None or mat.grease_pencil is None:
            mat = bpy.data.materials.new(name)
            bpy.data.materials.create_gpencil_data(mat)
            style = mat.grease_pencil
            style.show_stroke, style.show_fill = False, True
            style.fill_color = colour
            style.use_fill_holdout = holdout
        return mat

    own = next((m for m in mats if m is not None and m.grease_pencil is not None
                and m.grease_pencil.show_fill and not m.grease_pencil.use_fill_holdout), None)
    fill = slot(own if own is not None else gp_material(FILL_MATERIAL, False))
    return fill, slot(gp_material(HOLE_MATERIAL, True))


def layer_to_world(obj, layer):
    """The matrix taking a layer's drawing space to world space: through the layer's
    parent when it has one (then the object's own matrix does not apply)."""
    if layer.parent is not None:
        return layer.parent.matrix_world @ layer.matrix_parent_inverse @ layer.matrix_local
    return obj.matrix_world @ layer.matrix_local


def match_parent(layer, source) -> None:
    """Parent a new layer as ``source`` is, landing its strokes where the source's are.

    Parenting stores the inverse of the parent's matrix at that moment, read-only; if the
    parent has moved since the source was parented, the difference goes into the new
    layer's own transform: local = new_inverse^-1 @ source_inverse @ source_local.
    """
    layer.parent = source.parent
    local = (layer.matrix_parent_inverse.inverted() @ source.matrix_parent_inverse
             @ source.matrix_local)
    translation, rotation, scale = local.decompose()
    layer.translation, layer.rotation, layer.scale = translation, rotation.to_euler("XYZ"), scale


def place_above(gp, layer, below) -> None:
    """Move ``layer`` down to just above ``below`` in the layer group (or the main stack)
    both are in; a layer group between them is passed as one step."""
    if layer.parent_group != below.parent_group:
        return
    for _ in range(len(gp.layers) + len(gp.layer_groups)):
        names = [x.name for x in gp.layers]  # the whole tree, bottom to top
        at, under = names.index(layer.name), names.index(below.name)
        if at <= under + 1:
            return
        gp.layers.move(layer, "DOWN")


def write_results(obj, options, results: list[DrawingResult], context) -> object:
    """Write the results where ``options.output`` says; returns the object written to."""
    if options.as_curve:
        return write_curves(obj, options, results, context)
    sources = {r.layer.name: r.layer for r in results}
    if options.output == "REPLACE":
        for name, below in write_fills(obj.data, results).items():  # under the source
            place_above(obj.data, below, sources[name])
            if below.parent_group == sources[name].parent_group:
                obj.data.layers.move(below, "DOWN")  # now just under the source
        for r in results:
            if not r.chosen:  # an empty keyframe: nothing to replace
                continue
            drawing = r.frames[0].drawing
            drawing.remove_strokes(indices=r.chosen)
            write_strokes(drawing, r.new)
        return obj
    if options.output == "OBJECT":
        gp = grease_pencil_data().new(obj.data.name + " simplified")
        for mat in obj.data.materials:
            gp.materials.append(mat)
        target = context.blend_data.objects.new(obj.name + " simplified", gp)
        target.matrix_world = obj.matrix_world
        for coll in obj.users_collection:
            coll.objects.link(target)
    else:
        target, gp = obj, obj.data
    filled = write_fills(gp, results)
    made = {}
    for r in results:
        layer = r.layer
        if layer.name not in made:
            dest = new_layer_like(gp, layer, " simplified")
            if target is obj:
                place_above(gp, dest, layer)
            made[layer.name] = dest
            # a selection's source keeps its other strokes in view: only a layer simplified
            # whole is hidden
            if options.hide_source and options.scope != "SELECTED":
                layer.hide = True
        write_frames(made[layer.name], r.frames, r.new)
    if options.hide_source and options.scope != "SELECTED":
        for name, dest in made.items():
            keep_in_view(sources[name], dest)
    for name, below in filled.items():  # fills just under their lines
        if target is obj:  # the lines are just above the source: the fills go between
            place_above(gp, below, sources[name])
        elif name in made:  # a new object's layers stack as made: the lines go above
            place_above(gp, made[name], below)
    return target


def visible_spans(frames: list[int], keys: list[int]) -> list[tuple[int, int | None]]:
    """The frames a drawing shows at, as spans ``(first, end)``: from each of its keyframes
    ``frames`` to the layer's next keyframe of ``keys`` (its keyframe numbers, any order),
    ``end`` excluded (None: on to the end of time), spans that meet merged into one.

    >>> visible_spans([1, 9], [1, 5, 9, 13])
    [(1, 5), (9, 13)]
    >>> visible_spans([5, 9], [1, 5, 9, 13])  # two keyframes in a row share the drawing
    [(5, 13)]
    >>> visible_spans([13], [1, 5, 9, 13])
    [(13, None)]
    """
    keys = sorted(set(keys))
    spans: list[tuple[int, int | None]] = []
    for frame in sorted(set(frames)):
        later = [k for k in keys if k > frame]
        end = later[0] if later else None
        if spans and spans[-1][1] == frame:
            spans[-1] = (spans[-1][0], end)
        else:
            spans.append((frame, end))
    return spans


def key_visibility(ob, spans: list[tuple[int, int | None]], now: int) -> None:
    """Key ``ob`` shown (in the viewport and in renders) over ``spans`` and hidden
    elsewhere, and set it as it is at frame ``now``: booleans keyed hold their value to
    the next key."""
    keys: dict[int, bool] = {}
    for first, end in spans:
        keys.setdefault(first - 1, True)  # hidden before, unless another span ends there
        keys[first] = False
        if end is not None:
            keys[end] = True
    for frame, hidden in sorted(keys.items()):
        for prop in ("hide_viewport", "hide_render"):
            setattr(ob, prop, hidden)
            ob.keyframe_insert(prop, frame=frame)
    shown = any(first <= now and (end is None or now < end) for first, end in spans)
    ob.hide_viewport = ob.hide_render = not shown


def write_curves(obj, options, results: list[DrawingResult], context):
    """As Curve Object: a Bezier curve object for each drawing written, placed and parented
    as its layer's strokes are, with a material of the ink's colour. A layer with one
    keyframe gets one object, named "<object> <layer> simplified"; a layer with several (a
    shot) gets one object per drawing in a collection of that name, each keyed visible over
    the frames its drawing shows at (:func:`visible_spans`), so that the curves play and
    render as the drawing did. Hiding the source, the keyframes not simplified (outside the
    frame range, or not reached before a cancel) are written as drawn too, so that no
    frame goes blank; the source is hidden once every drawing of its layer is written.
    Returns the last object written (None when none)."""
    hide = options.hide_source and options.scope != "SELECTED"
    by_layer: dict[int, list[DrawingResult]] = {}
    for r in results:
        by_layer.setdefault(r.layer.as_pointer(), []).append(r)
    scene = context.scene
    target = None
    for rs in by_layer.values():
        layer = rs[0].layer
        keys = [f.frame_number for f in layer.frames]
        shown = [(r.new, [f.frame_number for f in r.frames]) for r in rs]
        if hide:
            done = {n for _, numbers in shown for n in numbers}
            shown += [(new, [number]) for number, new in as_drawn_besides(layer, done)]
        shown = [(new, numbers) for new, numbers in shown if new.knots]  # empty: nothing
        name = f"{obj.name} {layer.name} simplified"
        shot = len(keys) > 1
        collection = context.collection
        if shot:
            collection = bpy.data.collections.new(name)
            context.collection.children.link(collection)
        for new, numbers in sorted(shown, key=lambda item: min(item[1])):
            target = new_curve_object(f"{name} {min(numbers):04d}" if shot else name, obj,
                                      collection)
            _place_like_layer(target, obj, layer)
            _write_curve(target, obj, new)
            if shot:
                key_visibility(target, visible_spans(numbers, keys), scene.frame_current)
        if hide:
            layer.hide = True
    return target


def _place_like_layer(target, obj, layer) -> None:
    """Parent a curve object as the layer's strokes move: with the layer's parent, or the
    object (and through it the object's own parents), placed where the ink is now."""
    parent = layer.parent if layer.parent is not None else obj
    target.parent = parent
    target.matrix_parent_inverse = parent.matrix_world.inverted()
    target.matrix_basis = layer_to_world(obj, layer).copy()


def _write_curve(target, obj, new: NewStrokes) -> None:
    """The strokes as Bezier splines, each with a surface material of its ink's colour."""
    write_bezier_splines(target.data, new.knots, new.handles_left, new.handles_right,
                         list(new.cyclic), new.radius)
    slots = sorted(set(new.material_index.tolist())) or [0]
    for slot in slots:
        source = obj.data.materials[slot] if slot < len(obj.data.materials) else None
        target.data.materials.append(ink_material(source))
    index = {slot: k for k, slot in enumerate(slots)}
    for spline, slot in zip(target.data.splines, new.material_index.tolist()):
        spline.material_index = index[slot]


def result_name(layer, suffix: str) -> str:
    return layer.name + suffix


def earlier_result(gp, layer, suffix: str):
    """The layer an earlier run wrote ``layer``'s result to, in ``gp`` beside it (the same
    name, the same layer group), or None."""
    found = gp.layers.get(result_name(layer, suffix))
    if found is None or found.id_data != gp or (
            layer.id_data == gp and found.parent_group != layer.parent_group):
        return None
    return found


def new_layer_like(gp, layer, suffix: str):
    """The layer for ``layer``'s result, named after it, placed and drawn as it is: the
    same layer group (when in the same data), transform (so that its strokes land where
    the source's are), parent and look. A re-run writes into its earlier result's layer
    (:func:`write_frames` replaces the keyframes it writes) rather than stacking another."""
    again = earlier_result(gp, layer, suffix)
    if again is not None:
        return again
    group = layer.parent_group if layer.id_data == gp else None
    new = gp.layers.new(result_name(layer, suffix), set_active=False, layer_group=group)
    new.translation, new.rotation, new.scale = layer.translation, layer.rotation, layer.scale
    for name in LOOK:
        setattr(new, name, getattr(layer, name))
    if layer.parent is not None:
        match_parent(new, layer)
    return new


def keep_in_view(source, dest) -> None:
    """Give ``dest`` (the result layer of a hidden source) a copy of each of the source's
    keyframes it has no keyframe at, as drawn: a keyframe outside the frame range, or not
    reached before a cancel, shows what it showed, never nothing nor a later result."""
    for number, new in as_drawn_besides(source, {f.frame_number for f in dest.frames}):
        write_strokes(dest.frames.new(number).drawing, new)


def as_drawn_besides(source, written: set[int]) -> list[tuple[int, NewStrokes]]:
    """Each keyframe of the layer ``source`` not among the frame numbers ``written``, with
    its strokes as drawn: what a result shows there when the source is hidden."""
    return [(f.frame_number, NewStrokes.as_drawn(read_drawing(f.drawing)))
            for f in source.frames if f.frame_number not in written]


def write_fills(gp, results: list[DrawingResult]) -> dict:
    """A layer "<name> fills" for each source layer with fills, each drawing's fills at
    its keyframes; by source layer name. The caller places them."""
    filled = {}
    for r in results:
        if r.fills is not None and r.fills.knots:
            if r.layer.name not in filled:
                filled[r.layer.name] = new_layer_like(gp, r.layer, " fills")
            write_frames(filled[r.layer.name], r.frames, r.fills)
    return filled


def write_frames(dest, frames: list, new: NewStrokes) -> None:
    """New strokes on a layer at the keyframes of a source drawing: one drawing, shared by
    the keyframes that shared the source's."""
    numbers = {f.frame_number for f in dest.frames}
    for frame in frames:  # an earlier run's keyframes here are replaced
        if frame.frame_number in numbers:
            dest.frames.remove(frame.frame_number)
    first = frames[0].frame_number
    write_strokes(dest.frames.new(first).drawing, new)
    for frame in frames[1:]:
        dest.frames.copy(first, frame.frame_number, instance_drawing=True)
