"""Scheduling: the simplification of one Grease Pencil object or curve object. Its
drawings are read (:mod:`.read`), simplified here through the replay cache, in a pool, or
by an engine (a cluster), held across frames, and turned into results for :mod:`.write`.

Kept apart from the operator class so that the operator is only the Blender-facing shell
(poll, report, progress) and this stays testable on its own.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Iterator
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
from ..core.curves.memo import LruStore
from ..core.parallel import KeptPool, KeptRun
from ..core.replay_cache import sketch_digest, strokes_digest
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
    "HELD", "HELD_ENTRIES", "held_across_frames", "Holding", "KEPT_IDLE", "kept_pool",
    "POOL_FROM", "REPLAY", "results_of", "simplified_here", "simplify_curve_object",
    "simplify_object", "StepwiseRun", "stop_kept_pool", "stop_kept_pool_if_idle",
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


def _stable_wanted(options) -> bool:
    """Whether the run holds its keyframes to each other: asked for, over keyframes."""
    return bool(options.stable and options.scope in ("ALL", "RANGE"))


def results_of(obj, options, gathered: Gathered, outputs: list, report: RunReport,
               holding: Holding | None = None, made: dict[int, NewStrokes] | None = None
               ) -> list[DrawingResult]:
    """The new strokes of each drawing of ``gathered.prepared`` whose output is in
    ``outputs`` (None where it is not: a cancelled run gives only what finished), and the
    empty keyframes to keep; counts and skips go to ``report``. ``holding``: where every
    drawing finished, the run's :class:`Holding`, which has held them all already.
    ``made``: the new strokes of drawings made already from those outputs (as held), by
    index into ``gathered.prepared``."""
    if holding is not None:
        outputs = holding.held(outputs)
    finished = [k for k, out in enumerate(outputs) if out is not None]
    prepared = [gathered.prepared[k] for k in finished]
    outputs = [outputs[k] for k in finished]
    made = {} if made is None else made
    empty, held = gathered.empty, gathered.held
    fills = _fills_wanted(options)
    if _stable_wanted(options) and holding is None:
        outputs = held_across_frames(prepared, outputs)
    materials = fill_materials(obj) if fills and prepared else None
    results = []
    for k, p, out in zip(finished, prepared, outputs):
        if isinstance(out, SketchError):
            report.skipped.append(f"'{p.layer.name}' frame {p.frames[0].frame_number} ({out})")
            continue
        new = made.get(k)
        results.append(DrawingResult(
            p.layer, p.frames, p.chosen,
            new if new is not None else to_new_strokes(out.strokes, p.data, p.plane,
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


#: the pool a shot's drawings go to (:class:`core.parallel.KeptPool`), started by the
#: first run of :data:`POOL_FROM` drawings or more and kept between presses, so that the
#: redo panel's steps go back to the workers holding each drawing's result; stopped by
#: :func:`stop_kept_pool` (the add-on's unregister) or :func:`stop_kept_pool_if_idle`
_kept: KeptPool | None = None
_kept_used = 0.0  # time.monotonic() of its last use
#: seconds a kept pool may go unused before :func:`stop_kept_pool_if_idle` stops it (its
#: workers and what they keep: about 100 MB each, and up to KEPT_POINTS' bound)
KEPT_IDLE = 600.0


def kept_pool(jobs: int) -> KeptPool:
    """The kept pool, of ``jobs`` workers (started, or started again for another count)."""
    global _kept, _kept_used
    if _kept is None or not _kept.alive or _kept.jobs != jobs:
        stop_kept_pool()
        _kept = KeptPool(jobs)
    _kept_used = time.monotonic()
    return _kept


def stop_kept_pool() -> None:
    """Stop the kept pool's workers, if it runs."""
    global _kept
    if _kept is not None:
        _kept.close()
        _kept = None


def stop_kept_pool_if_idle() -> float | None:
    """For ``bpy.app.timers``: stop the kept pool once unused for :data:`KEPT_IDLE`
    seconds (None: the timer ends), or the seconds until it may be."""
    if _kept is None:
        return None
    left = KEPT_IDLE - (time.monotonic() - _kept_used)
    if left > 0:
        return left
    stop_kept_pool()
    return None


class StepwiseRun:
    """A run over the chosen drawings of a Grease Pencil object, advanced by :meth:`step`:
    the modal operator steps it from its timer (Blender stays drawn, Esc cancels),
    :func:`simplify_object` steps it through. :meth:`finish` turns what finished into
    results, whether the run ended or was cancelled, so that a cancelled run writes every
    drawing it finished and nothing of the others.

    Each drawing's output is, in this order: one already shown at these params (a lookup
    in :data:`REPLAY`: a step back in the redo panel); else, with ``engine`` (a cluster),
    ``engine(sketches, regions)``; with ``pool`` (a batch's :func:`core.parallel.local_pool`),
    :func:`core.simplify_all` there; from :data:`POOL_FROM` drawings on (unless ``jobs``
    is 1), the :func:`kept_pool`'s workers, which keep each drawing's result for the redo
    panel's next step, the merge loop run on to the slider's top (COVERED_EPSILON) so that
    no step up runs it again; else in this process through :data:`REPLAY`, a drawing a step.

    Args:
        obj, options, params, frame_number, frame_range, jobs, pool, engine: as for
        :func:`simplify_object`.
    """

    def __init__(self, obj, options, params: SimplifyParams, frame_number: int,
                 frame_range: tuple[int, int] | None = None, jobs: int | None = None,
                 pool=None, engine=None) -> None:
        self.obj, self.options, self.params = obj, options, params
        self.report = RunReport()
        self.t0 = time.perf_counter()
        self.gathered = gather_drawings(obj, options, frame_number, self.report, frame_range)
        self.fills = fills = _fills_wanted(options)
        prepared = self.gathered.prepared
        # Stable Across Frames held as the drawings finish, while the pool works on
        self._holding = Holding(prepared) if _stable_wanted(options) else None
        self._made: dict[int, NewStrokes] = {}  # new strokes made as drawings settle
        if engine is not None:  # everything there, at the first step
            self.outputs: list = [None] * len(prepared)
            self._at_once = lambda: engine([p.sketch for p in prepared], fills)
            self._here, self._kept = deque(), None
            return
        self._at_once = None
        self.outputs = [REPLAY.output(p.sketch, params, fills) for p in prepared]
        todo = [k for k, out in enumerate(self.outputs) if out is None]
        if jobs is None:
            jobs = default_jobs() if pool is not None or len(prepared) >= POOL_FROM else 1
        pooled = [k for k in todo if not REPLAY.has_result(prepared[k].sketch, params)] \
            if jobs > 1 else []
        in_pool = set(pooled)
        self._here = deque(k for k in todo if k not in in_pool)
        self._kept: tuple[KeptRun, list[int]] | None = None
        if not pooled:
            return
        sketches = [prepared[k].sketch for k in pooled]
        cover = max(params.epsilon, COVERED_EPSILON)
        records = [REPLAY.recorded(s, params) for s in sketches]
        if pool is not None:  # a batch's pool: all at the first step
            self._at_once = lambda: self._took(pooled, simplify_all(
                sketches, params, jobs, regions=fills, cover=cover, records=records,
                pool=pool))
        else:
            self._kept = (kept_pool(jobs).start(sketches, params, fills, cover, records),
                          pooled)

    @property
    def total(self) -> int:
        return len(self.outputs)

    @property
    def finished(self) -> int:
        return sum(out is not None for out in self.outputs)

    @property
    def done(self) -> bool:
        return self.finished == self.total

    def step(self, timeout: float | None = None) -> None:
        """Go on: take what the pool finished (waiting up to ``timeout`` seconds for one,
        None: until one finishes, when nothing is to be done here) and simplify one drawing
        here."""
        if self._at_once is not None:
            outputs, self._at_once = self._at_once(), None
            if outputs is not None:  # the engine's, all of them
                self.outputs = list(outputs)
            return
        if self._kept is not None:
            run, pooled = self._kept
            run.wait(0 if self._here else timeout)
            self._took(pooled, run.outputs)
            if run.done:
                self._kept = None
        if self._here:
            k = self._here.popleft()
            self.outputs[k] = simplified_here(self.gathered.prepared[k].sketch, self.params,
                                              self.fills)
        if self._holding is not None:
            self._holding.advance(self.outputs)
        self._make()

    def _make(self) -> None:
        """The new strokes of each drawing whose strokes are final (held, where the run
        holds its keyframes), made as it comes while the pool works on: the end of the
        run has only the last drawing's to make."""
        final = (self._holding.settled(self.outputs) if self._holding is not None else
                 ((k, out.strokes) for k, out in enumerate(self.outputs)
                  if out is not None and not isinstance(out, SketchError)))
        for k, strokes in final:
            if k not in self._made:
                p = self.gathered.prepared[k]
                self._made[k] = to_new_strokes(strokes, p.data, p.plane, self.outputs[k].width)

    def _took(self, pooled: list[int], outputs: list) -> None:
        """The pool's outputs (None: not yet) for drawings ``pooled``: kept for lookups,
        their merge records for rebuilds elsewhere."""
        for k, out in zip(pooled, outputs):
            if out is None or self.outputs[k] is not None:
                continue
            sketch = self.gathered.prepared[k].sketch
            if not isinstance(out, SketchError):
                if out.record is not None:
                    REPLAY.remember(sketch, self.params, out.record)
                REPLAY.keep_output(sketch, self.params, self.fills, out)
            self.outputs[k] = out

    def finish(self) -> list[DrawingResult]:
        """The results of the drawings finished so far (all of them unless cancelled)."""
        if not self.done:
            if self._kept is not None:
                self._kept[0].cancel()
            self.report.notes.append(f"cancelled: {self.finished} of {self.total} "
                                     "drawing(s) done, the rest left as they were")
        holding = self._holding if self.done else None  # else held over what finished
        if holding is not None:
            holding.advance(self.outputs)  # an engine's outputs: all at once
        # cancelled while holding, what finished is held again over itself: made again
        made = self._made if self.done or self._holding is None else None
        results = results_of(self.obj, self.options, self.gathered, self.outputs,
                             self.report, holding, made)
        self.report.seconds = time.perf_counter() - self.t0
        return results


def simplify_object(obj, options, params: SimplifyParams, frame_number: int,
                    progress=None, jobs: int | None = None,
                    frame_range: tuple[int, int] | None = None, engine=None, pool=None
                    ) -> tuple[RunReport, list[DrawingResult]]:
    """Simplify the chosen drawings of a Grease Pencil object; write nothing yet.

    Drawings are read here (:func:`gather_drawings`), simplified as :class:`StepwiseRun`
    says (in ``jobs`` processes: those of ``pool`` when given, a
    :func:`core.parallel.local_pool` kept by the caller across objects and files; by
    default the :func:`kept_pool` of all cores from :data:`POOL_FROM` drawings on, any in
    a given pool; in this process through the :data:`REPLAY` cache, so that a new epsilon
    for the same drawing is a replay; or by ``engine(sketches, regions)``, e.g. a Dask
    cluster, when given), and turned into new strokes here. ``progress`` is called with
    the fraction of drawings done.
    """
    run = StepwiseRun(obj, options, params, frame_number, frame_range, jobs, pool, engine)
    while not run.done:
        run.step()
        if progress is not None:
            progress(run.finished / run.total)
    results = run.finish()
    return run.report, results


#: held keyframes kept (:func:`held_across_frames`): a 13-keyframe shot shown at about 20
#: epsilons; each entry the strokes of one output, most of them shared with the outputs
#: :data:`REPLAY` keeps
HELD_ENTRIES = 256
#: Stable Across Frames' strokes, by what they were held from: the previous keyframe's
#: held strokes on this one's plane, this keyframe's output and its ink. A redo-panel step
#: holds again only the keyframes where one of these changed
HELD: LruStore[tuple, list] = LruStore(HELD_ENTRIES)


def held_across_frames(prepared: list[Prepared], outputs: list) -> list:
    """Each layer's results, keyframe by keyframe, held to the keyframe's before it
    (:func:`core.held_to`): the previous lines brought onto this drawing's plane, kept
    where this drawing's ink still runs along them within the bundle width, carried along
    where it moved. What was held from the same strokes before is looked up (:data:`HELD`)."""
    holding = Holding(prepared)
    holding.advance(outputs)
    return holding.held(outputs)


class Holding:
    """:func:`held_across_frames` a keyframe at a time, as a run's drawings finish: each
    layer's keyframes, in frame order, are held as far as the first not yet finished, so
    that a run holds while its pool works and :meth:`held` at the end is the same as
    holding then. Each keyframe is held once, through :data:`HELD`.

    Args:
        prepared: the drawings of the run, each with its layer and plane.
    """

    def __init__(self, prepared: list[Prepared]) -> None:
        self.prepared = prepared
        chains: dict[int, list[int]] = {}  # layer -> its drawings, in frame order
        for k in sorted(range(len(prepared)),
                        key=lambda k: prepared[k].frames[0].frame_number):
            chains.setdefault(prepared[k].layer.as_pointer(), []).append(k)
        self._chains = list(chains.values())
        self._next = [0] * len(self._chains)  # each chain's first keyframe not yet held
        self._previous: list[tuple | None] = [None] * len(self._chains)  # last strokes, plane
        self._held: dict[int, list] = {}  # drawing -> its held strokes

    def advance(self, outputs: list) -> None:
        """Hold every layer's keyframes whose output (None: not yet) and all before it in
        the layer are in ``outputs`` (a :class:`SketchError` is passed over)."""
        for c, chain in enumerate(self._chains):
            while self._next[c] < len(chain) and outputs[chain[self._next[c]]] is not None:
                k = chain[self._next[c]]
                self._next[c] += 1
                out = outputs[k]
                if isinstance(out, SketchError):
                    continue
                if self._previous[c] is not None:
                    self._held[k] = self._hold(k, out, *self._previous[c])
                self._previous[c] = (self._held.get(k, out.strokes), self.prepared[k].plane)

    def settled(self, outputs: list) -> Iterator[tuple[int, list]]:
        """Each drawing held so far (a :class:`SketchError` passed over), with its strokes
        as held: final, whatever finishes after it."""
        for c, chain in enumerate(self._chains):
            for k in chain[:self._next[c]]:
                if not isinstance(outputs[k], SketchError):
                    yield k, self._held.get(k, outputs[k].strokes)

    def held(self, outputs: list) -> list:
        """``outputs`` with the strokes of each keyframe held so far replaced."""
        return [replace(out, strokes=self._held[k]) if k in self._held else out
                for k, out in enumerate(outputs)]

    def _hold(self, k: int, out, strokes: list, was) -> list:
        """Drawing ``k``'s ``out`` held to the ``strokes`` before it, drawn on plane
        ``was``."""
        plane = self.prepared[k].plane
        moved = [stroke_moved(s, was, plane) for s in strokes]
        sketch = self.prepared[k].sketch
        key = (strokes_digest(moved), strokes_digest(out.strokes), out.width,
               sketch_digest(sketch))
        held = HELD.get(key)
        if held is None:
            held = held_to(moved, out.strokes, out.width, sketch.strokes)
            HELD.put(key, held)
        return held
