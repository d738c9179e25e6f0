"""Scheduling: the simplification of one Grease Pencil object or curve object. Its
drawings are read (:mod:`.read`), simplified here through the replay cache, in a pool, or
by an engine (a cluster), held across frames, and turned into results for :mod:`.write`.

Kept apart from the operator class so that the operator is only the Blender-facing shell
(poll, report, progress) and this stays testable on its own.
"""

from __future__ import annotations

import time
from dataclasses import replace

from ..core import (
    COVERED_EPSILON,
    ReplayCache,
    SimplifyParams,
    SketchError,
    default_jobs,
    held_to,
    simplified,
    simplify,
    simplify_all,
)
from .convert import (
    drawing_from_polylines,
    drawing_plane,
    fill_strokes,
    stroke_moved,
    to_new_strokes,
    to_sketch,
)
from .curve_io import read_curve
from .drawing import NewStrokes
from .read import Gathered, gather_drawings
from .records import DrawingResult, Prepared, RunReport
from .write import fill_materials

__all__ = [
    "held_across_frames", "POOL_FROM", "REPLAY", "results_of", "simplified_here",
    "simplify_curve_object", "simplify_object", "StepwiseRun",
]


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


#: from this many drawings on, the core runs them in a pool of processes it starts (about
#: 0.4 s); a pool already started (a batch's) takes any drawings, simplify_all running a
#: lone one here
POOL_FROM = 4
#: runs kept for replay: changing epsilon in the redo panel re-runs the operator
REPLAY = ReplayCache()


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
    bare: dict[str, int] = {}  # layers whose keyframes were all empty: named, not done
    for layer, frames in empty:
        if layer.as_pointer() not in drawn:
            bare[layer.name] = bare.get(layer.name, 0) + len(frames)
    report.skipped += [f"layer '{name}' (only empty keyframes: {n})" for name, n in bare.items()]
    results += [DrawingResult(layer, frames, [], NewStrokes.none()) for layer, frames in kept]
    if kept:
        report.notes.append(f"{len(kept)} empty keyframe(s) kept empty")
    return results


def simplified_here(sketch, params: SimplifyParams, fills: bool):
    """One drawing simplified in this process through :data:`REPLAY` (a new epsilon for
    the same drawing is a replay), or its :class:`SketchError`."""
    kept = REPLAY.output(sketch, params, fills)
    if kept is not None:
        return kept
    try:
        out = simplified(REPLAY.result(sketch, params), fills)
    except SketchError as exc:
        return exc
    REPLAY.keep_output(sketch, params, fills, out)
    return out


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
    else:  # a pool; an epsilon step in the redo panel looks up the outputs of an epsilon
        # already shown, replays kept results here, and rebuilds the drawings whose merge
        # records are kept, in the pool. A shot's first run covers the slider's whole range
        # (COVERED_EPSILON), so that no step up runs a merge loop again
        outputs = [REPLAY.output(p.sketch, params, fills) for p in prepared]
        todo = [k for k, p in enumerate(prepared)
                if outputs[k] is None and not REPLAY.has_result(p.sketch, params)]
        pooled = simplify_all([prepared[k].sketch for k in todo], params, jobs,
                              None if progress is None else lambda done, total, _k:
                              progress(done / len(prepared)), regions=fills,
                              cover=max(params.epsilon, COVERED_EPSILON),
                              records=[REPLAY.recorded(prepared[k].sketch, params)
                                       for k in todo], pool=pool) if todo else []
        for k, out in zip(todo, pooled):
            if not isinstance(out, SketchError):
                if out.record is not None:
                    REPLAY.remember(prepared[k].sketch, params, out.record)
                REPLAY.keep_output(prepared[k].sketch, params, fills, out)
            outputs[k] = out
        for k in range(len(prepared)):
            if outputs[k] is None:
                outputs[k] = simplified_here(prepared[k].sketch, params, fills)
    results = results_of(obj, options, gathered, outputs, report)
    report.seconds = time.perf_counter() - t0
    return report, results


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
