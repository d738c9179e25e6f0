"""The simplification of one Grease Pencil object: which drawings, then write the results.

Kept apart from the operator class so that the operator is only the Blender-facing shell
(poll, report, progress) and this stays testable on its own.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import bpy
import numpy as np

from ..core import (
    ReplayCache,
    SimplifyParams,
    Sketch,
    SketchError,
    default_jobs,
    held_to,
    simplified,
    simplify,
    simplify_all,
)
from .convert import (
    Plane,
    drawing_from_polylines,
    drawing_plane,
    far_out,
    fill_strokes,
    stroke_moved,
    to_new_strokes,
    to_sketch,
)
from .curve_io import ink_material, new_curve_object, read_curve, write_bezier_splines
from .drawing import DrawingData, NewStrokes
from .gp_io import grease_pencil_data, read_drawing, write_strokes

__all__ = [
    "collect_drawings", "DrawingResult", "FILL_MATERIAL", "fill_materials", "FLAT",
    "gather_drawings", "Gathered", "held_across_frames", "HOLE_MATERIAL", "keep_in_view",
    "layer_to_world",
    "LOOK", "match_parent", "new_layer_like", "place_above", "POOL_FROM", "Prepared", "REPLAY",
    "RESULT_SUFFIXES", "result_of", "results_of", "RunReport", "simplified_here",
    "simplify_curve_object", "simplify_object", "source_frames", "StepwiseRun",
    "target_layers", "untouchable_materials", "why_left_alone", "write_curve_result",
    "write_fills", "write_frames", "write_results",
]


@dataclass
class RunReport:
    drawings: int = 0
    strokes_in: int = 0
    strokes_out: int = 0
    seconds: float = 0.0
    skipped: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: the bundle width each drawing was simplified with, in its layer's units (d_eps)
    widths: list[float] = field(default_factory=list)

    def message(self) -> str:
        text = (f"Simplified {self.drawings} drawing(s): {self.strokes_in} strokes -> "
                f"{self.strokes_out} in {self.seconds:.2f} s")
        if self.widths:
            low, high = min(self.widths), max(self.widths)
            text += (f", bundle width {low:.3g}" if f"{low:.3g}" == f"{high:.3g}" else
                     f", bundle width {low:.3g} to {high:.3g}")
        if self.skipped:
            text += "; skipped " + ", ".join(self.skipped)
        if self.notes:
            text += "; " + ", ".join(self.notes)
        return text


@dataclass
class DrawingResult:
    """One simplified drawing: where it came from and what replaces it."""

    layer: object
    frames: list  # every keyframe showing the drawing
    chosen: list[int]  # the strokes simplified
    new: NewStrokes
    fills: NewStrokes | None = None  # its closed regions, when asked for


@dataclass
class Prepared:
    """A drawing ready for the core: where it came from, what was read of it, the strokes
    chosen, its plane, and the sketch made of them on that plane."""

    layer: object
    frames: list  # every keyframe showing the drawing
    data: DrawingData
    chosen: list[int]
    plane: Plane
    sketch: Sketch


def simplify_curve_object(obj, params: SimplifyParams) -> tuple[RunReport, NewStrokes | None]:
    """Simplify the splines of a curve object (object space)."""
    report = RunReport()
    t0 = time.perf_counter()
    polylines, closed, nurbs = read_curve(obj)
    if nurbs:
        report.notes.append(f"{nurbs} NURBS spline(s) read by their control points")
    if not polylines:
        report.skipped.append(f"'{obj.name}' (no spline with two points)")
        return report, None
    data = drawing_from_polylines(polylines, closed)
    plane = drawing_plane(data.positions)
    try:
        result = simplify(to_sketch(data, list(range(data.num_strokes)), plane), params)
    except SketchError as exc:
        report.skipped.append(f"'{obj.name}' ({exc})")
        return report, None
    new = to_new_strokes(result.strokes, data, plane, result.bundle_width)
    report.drawings, report.strokes_in, report.strokes_out = 1, len(polylines), len(new.knots)
    report.widths.append(result.bundle_width)
    report.seconds = time.perf_counter() - t0
    return report, new


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


#: the names a result layer gets after its source's
RESULT_SUFFIXES = (" simplified", " fills")


def why_left_alone(layer) -> str | None:
    """Why a layer may not be simplified: locked or hidden, itself or in a layer group
    (a locked group locks its layers, a hidden one hides them); None when it may."""
    if layer.lock or layer.hide:
        return "locked" if layer.lock else "hidden"
    group = layer.parent_group
    while group is not None:
        if group.lock or group.hide:
            return f"in {'locked' if group.lock else 'hidden'} group '{group.name}'"
        group = group.parent_group
    return None


def result_of(gp, layer):
    """The layer whose result (" simplified", " fills") ``layer`` is, beside it, or None."""
    for suffix in RESULT_SUFFIXES:
        if layer.name.endswith(suffix):
            source = gp.layers.get(layer.name[:-len(suffix)])
            if source is not None and source.parent_group == layer.parent_group:
                return source
    return None


def target_layers(gp, which: str, report: RunReport) -> list:
    """The layers to work on; locked and hidden ones (or in such groups) are left alone
    and named."""
    candidates = [gp.layers.active] if which == "ACTIVE" else list(gp.layers)
    out = []
    for layer in candidates:
        if layer is None:
            continue
        why = why_left_alone(layer)
        source = result_of(gp, layer)
        if source is not None:
            why = (f"the result of '{source.name}': replaced when '{source.name}' is "
                   "simplified again")
        if why == "hidden" and gp.layers.get(f"{layer.name} simplified") is not None:
            why = (f"hidden: simplified before into '{layer.name} simplified'; show it to "
                   "simplify it again")
        if why is None:
            out.append(layer)
        else:
            report.skipped.append(f"layer '{layer.name}' ({why})")
    return out


def untouchable_materials(obj) -> set[int]:
    """Material slots whose strokes are left alone: hidden or locked Grease Pencil
    materials (the artist has put those strokes out of reach)."""
    out = set()
    for k, mat in enumerate(obj.data.materials):
        style = getattr(mat, "grease_pencil", None) if mat is not None else None
        if style is not None and (style.hide or style.lock):
            out.add(k)
    return out


def source_frames(layer, scope: str, frame_number: int,
                  frame_range: tuple[int, int] | None = None) -> list:
    """The keyframes to simplify: the one shown at ``frame_number``; every one ("ALL",
    within ``frame_range`` when given); or those shown in ``frame_range`` ("RANGE": its
    keyframes and the one showing at its start, drawn before it)."""
    if scope == "ALL" and frame_range is None:
        return list(layer.frames)
    if scope in ("ALL", "RANGE") and frame_range is not None:
        lo, hi = frame_range
        showing = layer.get_frame_at(lo) if scope == "RANGE" else None
        first = showing.frame_number if showing is not None else lo
        return [f for f in layer.frames if first <= f.frame_number <= hi]
    frame = layer.get_frame_at(frame_number)
    return [frame] if frame is not None else []


#: what a new layer takes from its source layer for the strokes to look the same
LOOK = ("opacity", "blend_mode", "tint_color", "tint_factor", "use_lights", "radius_offset",
        "pass_index", "viewlayer_render", "use_masks", "channel_color")
#: a drawing whose points lie farther than this share of its size from its plane is not
#: flat: it is still flattened (the core works in 2D), and the report says by how much
FLAT = 0.02
#: from this many drawings on, the core runs them in a pool of processes it starts (about
#: 0.4 s); a pool already started (a batch's) takes any drawings, simplify_all running a
#: lone one here
POOL_FROM = 4
#: runs kept for replay: changing epsilon in the redo panel re-runs the operator
REPLAY = ReplayCache()


def collect_drawings(obj, options, frame_number: int, report: RunReport,
                     frame_range: tuple[int, int] | None = None) -> list[tuple]:
    """(layer, frames) for each distinct drawing to simplify: a drawing shared by several
    keyframes is listed once, with all of them. ``frame_range`` narrows "ALL" scope."""
    drawings: dict[int, tuple] = {}
    for layer in target_layers(obj.data, options.layers, report):
        for frame in source_frames(layer, options.scope, frame_number, frame_range):
            key = frame.drawing.as_pointer()
            if key in drawings:
                drawings[key][1].append(frame)
            else:
                drawings[key] = (layer, [frame])
    return list(drawings.values())


@dataclass
class Gathered:
    """The drawings of one object read for a run: what to simplify, the keyframes drawn
    empty (kept empty in the output when it has others), and how many strokes of hidden or
    locked materials were left alone."""

    prepared: list[Prepared]
    empty: list[tuple]
    held: int


def gather_drawings(obj, options, frame_number: int, report: RunReport,
                    frame_range: tuple[int, int] | None = None) -> Gathered:
    """Read the chosen drawings of a Grease Pencil object into sketches; what cannot be
    simplified goes to ``report``."""
    prepared = []
    empty = []  # keyframes drawn empty: kept empty in the output when it has others
    untouchable = untouchable_materials(obj)
    held = 0  # strokes of hidden or locked materials, left as they are
    for layer, frames in collect_drawings(obj, options, frame_number, report, frame_range):
        data = read_drawing(frames[0].drawing)
        where = f"'{layer.name}' frame {frames[0].frame_number}"
        if data.num_strokes == 0:
            if options.scope in ("ALL", "RANGE"):
                empty.append((layer, frames))
            else:
                report.skipped.append(f"an empty keyframe on {where}")
            continue
        usable = [k for k in range(data.num_strokes)
                  if (options.scope != "SELECTED" or data.selected[k])
                  and data.offsets[k + 1] - data.offsets[k] >= 2]
        chosen = [k for k in usable if int(data.material_index[k]) not in untouchable]
        held += len(usable) - len(chosen)
        if usable and not chosen:
            report.skipped.append(f"only strokes of hidden or locked materials on {where}")
            continue
        if not chosen:
            report.skipped.append(
                f"no stroke selected on {where}" if options.scope == "SELECTED"
                and not data.selected.any() else f"only strokes of one point on {where}")
            continue
        broken = far_out(data.positions)
        if broken.any():  # left out as a NaN is: the core drops them
            report.notes.append(f"{int(broken.sum())} point(s) far outside the drawing on "
                                f"{where} left out")
            data.positions = data.positions.copy()
            data.positions[broken] = np.nan
        points = data.positions[np.concatenate([np.arange(data.offsets[k], data.offsets[k + 1])
                                                for k in chosen])]
        if np.isfinite(points).all(axis=1).sum() < 2:  # drawing_plane leaves NaN points out
            report.skipped.append(f"a drawing without finite points on {where}")
            continue
        plane = drawing_plane(points)
        off = plane.off_plane(points)
        size = float(np.hypot(*np.ptp(plane.to_2d(points[np.isfinite(points).all(axis=1)]),
                                      axis=0)))
        if size > 0 and off > FLAT * size:
            report.notes.append(f"the drawing on {where} is not flat: points up to {off:.3g} "
                                f"off its plane ({100 * off / size:.0f}% of its size) were "
                                "flattened onto it")
        prepared.append(Prepared(layer, frames, data, chosen, plane,
                                 to_sketch(data, chosen, plane)))
    return Gathered(prepared, empty, held)


def _fills_wanted(options) -> bool:
    """Whether the run computes fill regions: asked for, and not for a curve object (which
    takes no fills)."""
    return bool(options.fill_regions and not options.as_curve)


def results_of(obj, options, gathered: Gathered, outputs: list, report: RunReport
               ) -> list[DrawingResult]:
    """The new strokes of each drawing whose output is in ``outputs`` (the first
    ``len(outputs)`` of ``gathered.prepared``: a cancelled run gives only what finished),
    and the empty keyframes to keep; counts and skips go to ``report``."""
    prepared = gathered.prepared[:len(outputs)]
    empty, held = gathered.empty, gathered.held
    fills = _fills_wanted(options)
    if options.stable and options.scope in ("ALL", "RANGE"):
        outputs = held_across_frames(prepared, outputs)
    materials = fill_materials(obj) if fills and prepared else None
    results = []
    for p, out in zip(prepared, outputs):
        if isinstance(out, SketchError):
            report.skipped.append(f"'{p.layer.name}' frame {p.frames[0].frame_number} ({out})")
            continue
        results.append(DrawingResult(
            p.layer, p.frames, p.chosen, to_new_strokes(out.strokes, p.data, p.plane,
                                                        out.width),
            fill_strokes(out.regions, p.plane, *materials) if materials else None))
        report.drawings += 1
        report.strokes_in += len(p.chosen)
        report.strokes_out += len(out.strokes)
        report.widths.append(out.width)
    if options.fill_regions and options.as_curve:
        report.notes.append("no fills on curve objects")
    if held:
        report.notes.append(f"{held} stroke(s) of hidden or locked materials left alone")
    # an empty keyframe hides the drawing before it from its frame on: so must the output's
    drawn = {r.layer.as_pointer() for r in results}
    kept = [(layer, frames) for layer, frames in empty if layer.as_pointer() in drawn]
    results += [DrawingResult(layer, frames, [], NewStrokes.none()) for layer, frames in kept]
    if kept:
        report.notes.append(f"{len(kept)} empty keyframe(s) kept empty")
    return results


def simplified_here(sketch, params: SimplifyParams, fills: bool):
    """One drawing simplified in this process through :data:`REPLAY` (a new epsilon for
    the same drawing is a replay), or its :class:`SketchError`."""
    try:
        return simplified(REPLAY.result(sketch, params), fills)
    except SketchError as exc:
        return exc


class StepwiseRun:
    """A run over many drawings a few at a time, for the modal operator: each
    :meth:`step` simplifies the next drawing (through :data:`REPLAY`); :meth:`finish`
    turns what finished into results, whether the run ended or was cancelled, so that a
    cancelled run writes every drawing it finished and nothing of the others.

    Args:
        obj, options, params, frame_number, frame_range: as for :func:`simplify_object`.
    """

    def __init__(self, obj, options, params: SimplifyParams, frame_number: int,
                 frame_range: tuple[int, int] | None = None) -> None:
        self.obj, self.options, self.params = obj, options, params
        self.report = RunReport()
        self.t0 = time.perf_counter()
        self.gathered = gather_drawings(obj, options, frame_number, self.report, frame_range)
        self.fills = _fills_wanted(options)
        self.outputs: list = []

    @property
    def total(self) -> int:
        return len(self.gathered.prepared)

    @property
    def done(self) -> bool:
        return len(self.outputs) == self.total

    def step(self) -> None:
        """Simplify the next drawing."""
        item = self.gathered.prepared[len(self.outputs)]
        self.outputs.append(simplified_here(item.sketch, self.params, self.fills))

    def finish(self) -> list[DrawingResult]:
        """The results of the drawings finished so far (all of them unless cancelled)."""
        if not self.done:
            self.report.notes.append(f"cancelled: {len(self.outputs)} of {self.total} "
                                     "drawing(s) done, the rest left as they were")
        results = results_of(self.obj, self.options, self.gathered, self.outputs,
                             self.report)
        self.report.seconds = time.perf_counter() - self.t0
        return results


def simplify_object(obj, options, params: SimplifyParams, frame_number: int,
                    progress=None, jobs: int | None = None,
                    frame_range: tuple[int, int] | None = None, engine=None, pool=None
                    ) -> tuple[RunReport, list[DrawingResult]]:
    """Simplify the chosen drawings of a Grease Pencil object; write nothing yet.

    Drawings are read here (:func:`gather_drawings`), simplified by the core (in ``jobs``
    processes, those of ``pool`` when given, a :func:`core.parallel.local_pool` kept by
    the caller across objects and files; by default a pool of all cores from
    :data:`POOL_FROM` drawings on, any in a given pool; in this
    process through the :data:`REPLAY` cache, so that a new epsilon for the same drawing is
    a replay; or by ``engine(sketches, regions)``, e.g. a Dask cluster, when given), and
    turned into new strokes here. ``progress`` is called with the fraction of drawings done.
    """
    report = RunReport()
    t0 = time.perf_counter()
    gathered = gather_drawings(obj, options, frame_number, report, frame_range)
    prepared = gathered.prepared
    if jobs is None:
        jobs = default_jobs() if pool is not None or len(prepared) >= POOL_FROM else 1
    fills = _fills_wanted(options)
    if engine is not None:
        outputs = engine([p.sketch for p in prepared], fills)
    elif jobs == 1:  # here, through the replay cache: the redo panel's slider replays
        outputs = []
        for k, item in enumerate(prepared):
            outputs.append(simplified_here(item.sketch, params, fills))
            if progress is not None:
                progress((k + 1) / len(prepared))
    else:  # a pool; an epsilon step in the redo panel replays kept results here, and
        # rebuilds the drawings whose merge records are kept, in the pool
        todo = [k for k, p in enumerate(prepared) if not REPLAY.has_result(p.sketch, params)]
        pooled = simplify_all([prepared[k].sketch for k in todo], params, jobs,
                              None if progress is None else lambda done, total, _k:
                              progress(done / len(prepared)), regions=fills,
                              cover=max(REPLAY.cover(prepared[k].sketch, params)
                                        for k in todo),
                              records=[REPLAY.recorded(prepared[k].sketch, params)
                                       for k in todo], pool=pool) if todo else []
        outputs = [None] * len(prepared)
        for k, out in zip(todo, pooled):
            if not isinstance(out, SketchError) and out.record is not None:
                REPLAY.remember(prepared[k].sketch, params, out.record)
            outputs[k] = out
        for k in sorted(set(range(len(prepared))) - set(todo)):
            outputs[k] = simplified_here(prepared[k].sketch, params, fills)
    results = results_of(obj, options, gathered, outputs, report)
    report.seconds = time.perf_counter() - t0
    return report, results


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


def held_across_frames(prepared: list[Prepared], outputs: list) -> list:
    """Each layer's results, keyframe by keyframe, held to the keyframe's before it
    (:func:`core.held_to`): the previous lines brought onto this drawing's plane, kept
    where this drawing's ink still runs along them within the bundle width, carried along
    where it moved."""
    out = list(outputs)
    previous: dict[int, tuple] = {}  # layer -> (its last strokes, their plane)
    order = sorted(range(len(prepared)), key=lambda k: (prepared[k].layer.as_pointer(),
                                                        prepared[k].frames[0].frame_number))
    for k in order:
        layer, plane = prepared[k].layer, prepared[k].plane
        if isinstance(out[k], SketchError):
            continue
        before = previous.get(layer.as_pointer())
        if before is not None:
            strokes, was = before
            out[k] = replace(out[k], strokes=held_to(
                [stroke_moved(s, was, plane) for s in strokes], out[k].strokes, out[k].width,
                prepared[k].sketch.strokes))
        previous[layer.as_pointer()] = (out[k].strokes, plane)
    return out


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
    if options.as_curve:  # one curve object a layer, placed like the layer's strokes
        target, done = None, set()
        for r in results:
            if r.layer.name in done:
                continue  # a curve object holds one drawing of a layer: the first
            done.add(r.layer.name)
            target = new_curve_object(f"{obj.name} {r.layer.name} simplified", obj,
                                      context.collection)
            # parented as the layer's strokes move: with the layer's parent, or the object
            # (and through it the object's own parents), placed where the ink is now
            parent = r.layer.parent if r.layer.parent is not None else obj
            world = layer_to_world(obj, r.layer)
            target.parent = parent
            target.matrix_parent_inverse = parent.matrix_world.inverted()
            target.matrix_basis = world.copy()
            write_bezier_splines(target.data, r.new.knots, r.new.handles_left,
                                 r.new.handles_right, list(r.new.cyclic), r.new.radius)
            slots = sorted(set(r.new.material_index.tolist())) or [0]
            for slot in slots:
                source = obj.data.materials[slot] if slot < len(obj.data.materials) else None
                target.data.materials.append(ink_material(source))
            index = {slot: k for k, slot in enumerate(slots)}
            for spline, slot in zip(target.data.splines, r.new.material_index.tolist()):
                spline.material_index = index[slot]
            if options.hide_source and options.scope != "SELECTED":
                r.layer.hide = True
        return target
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
    have = {f.frame_number for f in dest.frames}
    for frame in source.frames:
        if frame.frame_number not in have:
            write_strokes(dest.frames.new(frame.frame_number).drawing,
                          NewStrokes.as_drawn(read_drawing(frame.drawing)))


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
