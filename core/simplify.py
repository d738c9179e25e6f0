"""The public entry point: ``simplify(sketch, params) -> SimplifyResult``.

Under "auto" alpha a sparse drawing is tried wider than ``tuning.loose_alpha`` first
(:meth:`SimplifyParams.widths`: its ink's own width, then halfway down, each unless its
lines lie in bands that wide, passes that wander across each other being one loose line,
not a band), and a wider result is kept only where it keeps the ink: at most
``tuning.keep_left`` of the drawing's ink, and ``tuning.keep_stroke`` of any one stroke,
farther than ``tuning.keep_reach`` of its diagonal (or its canvas's, if smaller) from the
output. It is judged at :data:`KEEP_EPSILON` whatever the epsilon asked, so that the width
is the drawing's and every epsilon replays one merge history. Otherwise the narrow
width's result.

How the wider widths were measured (190 sketches, with the complex stage then the
default): ``docs/decisions.md``, "Wider where the ink allows (moved from core.simplify)".

Invariants: a drawing that is not sparse, or whose alpha is a number, is simplified once,
as before; a wider result is never kept that leaves more ink out than keep_left.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import shapely

from .arrays.geometry import Reached, polygons_from
from .complex.base_complex import BaseComplex, build_base_complex
from .complex.complex_state import ComplexState, Merge
from .complex.noding import more_crossings_than
from .curves.attributes import NearestInk
from .curves.bezier import sample_bezier
from .curves.fills import line_regions
from .curves.memo import StrokeMemo
from .io.cleaning import (
    CleaningReport,
    Normalisation,
    clean_sketch,
    drawing_part_areas,
    drawing_strokes,
    normalised_strokes,
)
from .lines import PenRun, lines_from_pen
from .lines.work import Work
from .merge.agglomeration import AgglomerationStats, agglomerate
from .params import ResolvedParams, SimplifyParams, Tuning
from .sketch import Region, Sketch, SketchError, Stroke

#: the epsilon at which a wider width is judged: the default one
KEEP_EPSILON = SimplifyParams.epsilon

#: fills follow each output Bezier this many steps a cubic
FILL_SAMPLES = 16


@dataclass(frozen=True)
class Prepared:
    """A sketch ready for the complex (stage 1): cleaned, in its drawing's unit frame."""

    #: the input cleaned of non-finite points, duplicates and strokes of one point
    cleaned: Sketch
    #: what cleaning dropped or mended
    report: CleaningReport
    #: the cleaned strokes in the unit frame (the drawing's diagonal 1)
    unit: list[np.ndarray]
    #: the unit frame: to and from the input's coordinates
    norm: Normalisation
    #: the input ink, whose width, pressure and style the lines carry (stage 6)
    ink: NearestInk

    @cached_property
    def drawing(self) -> list[np.ndarray]:
        """The drawing's strokes in the unit frame, without ink far away from it."""
        return drawing_strokes(self.unit, self.norm.box)


def prepare(sketch: Sketch) -> Prepared:
    """Stage 1: the sketch cleaned and in its drawing's unit frame
    (:mod:`core.io.cleaning`)."""
    cleaned, report = clean_sketch(sketch)
    unit, norm = normalised_strokes(cleaned)
    return Prepared(cleaned, report, unit, norm, NearestInk(cleaned.strokes, unit))


def build_complex(prepared: Prepared, params: ResolvedParams) -> BaseComplex:
    """Stage 3: the base complex of the strokes (:mod:`core.complex`, paper 3.1).

    ``params.max_curves`` bounds each drawing part (:func:`core.io.cleaning.drawing_parts`:
    ink apart from the rest, as the drawings of a page are), before noding by its strokes'
    crossings and after by its curves: the merge loop's cost grows with a part's
    tangle, and a page of many drawings, each within the limit, is simplified whole. A
    part over it is refused by a message that names it, where it lies and how to split it.
    """
    limit = params.max_curves
    if limit is None:
        return build_base_complex(prepared.unit)
    labels, areas = drawing_part_areas(prepared.unit)
    order = np.argsort(labels, kind="stable")  # each part's strokes, in one pass
    for part, members in enumerate(np.split(order, np.cumsum(np.bincount(labels))[:-1])):
        crossings = more_crossings_than([prepared.unit[k] for k in members], limit // 2)
        if crossings is not None:
            raise SketchError(_too_tangled(prepared, labels, part,
                                           f"crosses itself over {crossings} times", limit))
    cx = build_base_complex(prepared.unit)
    if cx.num_curves > limit:
        firsts = shapely.points(np.array([c[0] for c in cx.curves]))
        curve, part = shapely.STRtree(areas).query(firsts, predicate="intersects")
        per_part = np.bincount(part[np.unique(curve, return_index=True)[1]],
                               minlength=len(areas))
        if per_part.max() > limit:
            worst = int(np.argmax(per_part))
            raise SketchError(_too_tangled(prepared, labels, worst,
                                           f"crosses into {per_part[worst]} curves", limit))
    return cx


def _too_tangled(prepared: Prepared, labels: np.ndarray, part: int, how: str, limit: int
                 ) -> str:
    """The message for a drawing part over ``max_curves``: which part, where, how to split."""
    mine = np.flatnonzero(labels == part)
    box = np.concatenate([prepared.norm.from_unit(prepared.unit[k]) for k in mine])
    (x0, y0), (x1, y1) = box.min(axis=0), box.max(axis=0)
    parts = int(labels.max()) + 1
    where = f"drawing part {part + 1} of {parts} " if parts > 1 else "the drawing "
    return (f"{where}({len(mine)} strokes, x {x0:.4g} to {x1:.4g}, y {y0:.4g} to {y1:.4g}) "
            f"{how}: too tangled to simplify at once (max_curves = {limit}). Simplify its "
            "strokes a few at a time: in Blender, select some and run with Selected "
            "Strokes; from the command line, split the file")


@dataclass
class SimplifyResult:
    """Output strokes (input coordinates) and everything that led to them."""

    strokes: list[Stroke]
    params: ResolvedParams
    complex: BaseComplex  # the initial base complex, unit frame
    state: ComplexState  # the simplified complex: alive curves and patches
    history: list[Merge]  # every merge applied, in order, with its cost
    counts: dict[str, dict[str, int]]
    timings: dict[str, float]
    stats: AgglomerationStats | None = None
    #: for each stroke of :attr:`cleaned`, the output stroke that draws most of it (-1:
    #: none): the grouping the lines made, to measure against labels
    groups: np.ndarray | None = None
    #: the cleaned input in its unit frame, which a replay draws its lines from again
    _prepared: Prepared | None = field(default=None, repr=False)
    _memo: StrokeMemo = field(default_factory=StrokeMemo, repr=False)  # shared by .at()
    #: the merge loop's whole record, where it ran on past ``params.epsilon`` (``cover``)
    _recorded: list[Merge] | None = field(default=None, repr=False)
    _covers: float | None = field(default=None, repr=False)

    @property
    def record(self) -> list[Merge]:
        """Every merge the loop recorded, up to :attr:`covers` (what :meth:`at` replays)."""
        return self.history if self._recorded is None else self._recorded

    @property
    def covers(self) -> float:
        """The largest epsilon :meth:`at` can replay: ``params.epsilon``, or the ``cover``
        the merge loop ran on to."""
        return self.params.epsilon if self._covers is None else max(self._covers,
                                                                    self.params.epsilon)

    @property
    def cleaned(self) -> Sketch:
        """The input as simplified: cleaned of non-finite points, duplicates and strokes
        of one point, in the input's coordinates (each stroke keeps its ids)."""
        return self._prepared.cleaned

    @property
    def normalisation(self) -> Normalisation:
        """The drawing's unit frame: to and from the input's coordinates."""
        return self._prepared.norm

    @property
    def cleaning(self) -> CleaningReport:
        """What cleaning dropped or mended."""
        return self._prepared.report

    @property
    def bundle_width(self) -> float:
        """The bundle width used, d_eps = alpha * D, in the sketch's own units."""
        return self.params.alpha * self.normalisation.scale

    def pen_passes(self, picture: Callable[[str, Work], None]) -> PenRun:
        """The pen stage (:func:`core.lines.lines_from_pen`) run again on this result's
        simplified complex and cleaned strokes, handing the work after each pass to
        ``picture`` (debug pictures, ``scripts/pen_passes.py``). The stage is a function of
        the complex, the params and the strokes alone, so these are the lines a pen-stage
        run made."""
        return lines_from_pen(self.state, self.params, self._prepared.unit,
                              picture=picture)

    def to_sketch(self) -> Sketch:
        src = self.cleaned
        return Sketch(list(self.strokes), src.width, src.height)

    def at(self, epsilon: float) -> SimplifyResult:
        """The result ``simplify`` gives at another ``epsilon`` up to :attr:`covers`, by
        replaying the recorded merges (it equals a fresh run exactly)."""
        if not 0 <= epsilon <= self.covers:
            raise SketchError(f"epsilon {epsilon} is outside 0..{self.covers}, the "
                              "range this result's merge history covers")
        t0 = time.perf_counter()
        record = self.record
        state = _replayed(self.complex, record, replace(self.params, epsilon=epsilon))
        params = replace(self.params, epsilon=epsilon)
        timings = {"replay": time.perf_counter() - t0}
        out = _finish(self._prepared, self.complex, state, record[:state.merges_applied], params,
                      None, timings, self._memo)
        out._recorded, out._covers = record, self.covers
        return out

    def fill_regions(self, min_share: float | None = None) -> list[Region]:
        """The closed regions of the clean lines to fill, as plain rings (input
        coordinates), largest first (:func:`core.curves.fills.line_regions`): the white
        spaces the output strokes enclose, where two lines that stop within
        twice ``tuning.fill_close`` bundle widths of each other close a region, leaving out
        slivers smaller than ``min_share`` (default ``tuning.fill_min_share``) of the area of
        the drawing's box. A region lying inside
        another (touching it nowhere) is a hole of it, and is filled only inside a hole in
        turn (the even-odd rule of vector art: a ring's hole stays empty, a face's eyes
        are cut out of it, a pupil inside an eye is filled); regions side by side are
        each filled."""
        t = self.params.tuning
        min_share = t.fill_min_share if min_share is None else min_share
        smallest = min_share * 0.5 * self.normalisation.scale ** 2  # box of diagonal D
        # the curves as drawn, not the chords between a stroke's points (which sample its
        # Bezier coarsely), so that a fill reaches the line all round
        drawn = [s.points if s.bezier is None else sample_bezier(s.bezier, FILL_SAMPLES)
                 for s in self.strokes]
        return line_regions(drawn, [s.closed for s in self.strokes],
                            t.fill_close * self.bundle_width, smallest,
                            t.fill_reach * self.bundle_width)

    def regions(self) -> list[shapely.Polygon]:
        """The patches left, as polygons in input coordinates (what a fill can use), with
        their holes: a drawing inside a patch, touching it nowhere, is a hole in it."""
        cx = self.complex
        base = polygons_from([cx.ring_points(p.boundary) for p in cx.patches]) \
            if cx.patches else []
        for k, patch in enumerate(cx.patches):
            if patch.holes:
                base[k] = shapely.Polygon(base[k].exterior,
                                          [cx.ring_points(h) for h in patch.holes])
        out = []
        for p in self.state.alive_patches():
            poly = shapely.union_all([base[k] for k in self.state.patch_origin[p]])
            out.append(shapely.transform(poly, self.normalisation.from_unit))
        return out


def _counts(nodes: int, curves: int, patches: int, strokes: int) -> dict[str, int]:
    return {"strokes": strokes, "nodes": nodes, "curves": curves, "patches": patches}


def _finish(prepared: Prepared, cx: BaseComplex, state: ComplexState, history: list[Merge],
            params: ResolvedParams, stats: AgglomerationStats | None,
            timings: dict[str, float], memo: StrokeMemo | None = None) -> SimplifyResult:
    """Stages 5 and 6 on a simplified complex: the lines drawn from the pen
    (:mod:`core.lines`), then the ink's attributes carried onto them, back in the input's
    coordinates. A fresh run, a replay and a rebuild from a record all end here."""
    t0 = time.perf_counter()
    memo = StrokeMemo() if memo is None else memo
    ink, norm, sketch = prepared.ink, prepared.norm, prepared.cleaned
    pen = lines_from_pen(state, params, prepared.unit, memo)
    fitted = pen.work.fitted
    timings = {**timings, **{f"pen.{k}": v for k, v in pen.seconds.items()}}
    t1 = time.perf_counter()
    strokes = []
    for f, ink_of in zip(fitted, ink.transfer([f.points for f in fitted])):
        strokes.append(Stroke(norm.from_unit(f.points), width=ink_of.width,
                              pressure=ink_of.pressure, style=ink_of.style,
                              bezier=norm.from_unit(f.bezier), closed=f.closed,
                              sources=ink_of.sources))
    timings = {**timings, "strokes": t1 - t0, "attributes": time.perf_counter() - t1}
    nodes_after = len({n for c in state.alive_curves() for n in state.curve_nodes[c]})
    counts = {
        "before": _counts(cx.num_nodes, cx.num_curves, cx.num_patches, len(sketch.strokes)),
        "after": _counts(nodes_after, state.num_curves, state.num_patches, len(strokes)),
    }
    return SimplifyResult(strokes, params, cx, state, history, counts, timings, stats,
                          pen.work.groups, prepared, memo)


def simplify(sketch: Sketch, params: SimplifyParams | None = None,
             cover: float | None = None) -> SimplifyResult:
    """Simplify a rough sketch into few long smooth strokes.

    Args:
        sketch: the rough strokes.
        params: what controls it (default :class:`SimplifyParams`).
        cover: run the merge loop on to this epsilon, so that the result's :meth:`at`
            replays any epsilon up to it (a slider), the output still made at
            ``params.epsilon`` only.

    Raises :class:`SketchError` for input that cannot be a sketch or bad parameters.
    """
    params = params if params is not None else SimplifyParams()
    if not isinstance(params, SimplifyParams):
        raise SketchError(f"params must be SimplifyParams, got {type(params).__name__}")
    t0 = time.perf_counter()
    with _out_of_memory_said(sketch):
        prepared = prepare(sketch)                        # 1. clean, into the unit frame
        *wider, params = params.widths(prepared.drawing)  # 2. the width: follows the ink
        t1 = time.perf_counter()
        cx = build_complex(prepared, params)              # 3. the base complex (3.1)
        timings = {"clean": t1 - t0, "complex": time.perf_counter() - t1}
        # 4-6. agglomerate (3.2), draw the lines, carry the ink's attributes: a wider width
        # first where the drawing is sparse, kept where its result keeps the ink
        result = (_wider_kept(prepared, cx, wider, timings, cover)
                  or _run(prepared, cx, params, timings, cover))
    if not result.strokes and result.params.epsilon > 0:
        # every stroke of the drawing shorter than the bundle width, as where ink far away
        # holding much of the points sets the drawing's size: say so, rather than give back
        # an empty drawing as if simplified
        raise SketchError(
            f"nothing would come out: every stroke is shorter than the bundle width "
            f"({result.params.alpha:.3g} of the drawing's diagonal, "
            f"{prepared.norm.scale:.3g}); is "
            "part of the ink far away from the rest? Simplify the parts apart, or at "
            "epsilon 0")
    result.timings["total"] = time.perf_counter() - t0
    return result


@contextmanager
def _out_of_memory_said(sketch: Sketch) -> Iterator[None]:
    """Running out of memory (numpy's MemoryError, GEOS's bad_alloc) said as a
    :class:`SketchError` naming the sketch's size and what to do, not a traceback: the
    caller's strokes are untouched either way."""
    try:
        yield
    except (MemoryError, shapely.errors.GEOSException) as exc:
        if not isinstance(exc, MemoryError) and "bad_alloc" not in str(exc):
            raise
        points = sum(len(s.points) for s in sketch.strokes)
        raise SketchError(f"out of memory simplifying {len(sketch.strokes)} strokes "
                          f"({points} points): simplify fewer at once (the strokes "
                          "selected, or the drawing's parts apart)") from exc


def from_record(sketch: Sketch, params: SimplifyParams, record: list[Merge],
                covers: float) -> SimplifyResult:
    """The result of an earlier run, rebuilt from its merge record without the merge
    loop: the base complex built again (deterministically: the record's ids name the same
    curves and patches) and the recorded merges cheaper than ``params.epsilon`` replayed;
    what a fresh run gives, exactly. ``params`` are the run's resolved params (its
    ``result.params``, or params with the same numbers: :meth:`ResolvedParams.of`) at any
    epsilon up to ``covers``, the epsilon the record reaches. A run in another process
    sends back its record (a few MB at most), not its whole result."""
    params = ResolvedParams.of(params)
    if not 0 <= params.epsilon <= covers:
        raise SketchError(f"epsilon {params.epsilon} is outside 0..{covers}, the range "
                          "this record covers")
    t0 = time.perf_counter()
    prepared = prepare(sketch)
    cx = build_base_complex(prepared.unit)
    state = _replayed(cx, record, params)
    timings = {"rebuild": time.perf_counter() - t0}
    out = _finish(prepared, cx, state, record[:state.merges_applied], params, None, timings)
    out._recorded, out._covers = list(record), covers
    return out


def _replayed(cx: BaseComplex, record: list[Merge], params: ResolvedParams) -> ComplexState:
    """The complex after the recorded merges a run at ``params.epsilon`` applies: those
    cheaper than it, up to the targets (the merge loop's own stopping rule)."""
    state = ComplexState(cx)
    for merge in record:
        if merge.cost >= params.epsilon or state.targets_reached(params.target_patches,
                                                                 params.target_curves):
            break
        state.apply(merge)
    return state


def _wider_kept(prepared: Prepared, cx: BaseComplex, wider: list[ResolvedParams],
                timings: dict[str, float], cover: float | None) -> SimplifyResult | None:
    """The result at the first of the ``wider`` widths whose lines keep the ink
    (:func:`_keeps_ink`), judged at :data:`KEEP_EPSILON` whatever the epsilon asked, then
    replayed to it; None where none does."""
    if not wider:
        return None
    cleaned, norm = prepared.cleaned, prepared.norm
    t = wider[0].tuning
    reach = t.keep_reach * min(1.0, np.hypot(cleaned.width, cleaned.height) / norm.scale
                               if cleaned.width and cleaned.height else 1.0)
    drawing = prepared.drawing
    for wide in wider:
        run = _run(prepared, cx, replace(wide, epsilon=max(wide.epsilon, KEEP_EPSILON)),
                   timings, cover)
        judged = run if run.params.epsilon == KEEP_EPSILON else run.at(KEEP_EPSILON)
        if _keeps_ink(drawing, [norm.to_unit(s.points) for s in judged.strokes], reach, t):
            return run if wide.epsilon == run.params.epsilon else run.at(wide.epsilon)
    return None


def _run(prepared: Prepared, cx: BaseComplex, params: ResolvedParams,
         timings: dict[str, float], cover: float | None = None) -> SimplifyResult:
    """Stage 4, the merge loop (:mod:`core.merge`, paper 3.2), then stages 5 and 6 on the
    base complex, at one resolved width; with ``cover`` above epsilon, the loop runs on to
    it (recorded for :meth:`at`) and the lines are drawn at epsilon alone."""
    t0 = time.perf_counter()
    on = cover is not None and cover > params.epsilon
    record, state, stats = agglomerate(cx, replace(params, epsilon=cover) if on else params)
    history = record
    if on:
        state = _replayed(cx, record, params)
        history = record[:state.merges_applied]
    timings = {**timings, "agglomerate": time.perf_counter() - t0}
    out = _finish(prepared, cx, state, history, params, stats, timings)
    if on:
        out._recorded, out._covers = record, cover
    return out


def _keeps_ink(drawing: list[np.ndarray], lines: list[np.ndarray], reach: float,
               tuning: Tuning) -> bool:
    """Whether ``lines`` keep the ink of ``drawing`` (unit-frame polylines, sampled every
    ``tuning.keep_reach`` / 8 of the drawing's diagonal, whatever ``reach``, so that the
    samples are bounded by the ink, not by a canvas the file says is tiny): at most
    ``tuning.keep_left`` of it, and at most ``tuning.keep_stroke`` of any one stroke,
    farther than ``reach`` from every line.

    >>> x = np.linspace(0, 1, 11)[:, None]
    >>> ink = [np.hstack([x, 0 * x]), np.hstack([x, 0.03 + 0 * x])]
    >>> _keeps_ink(ink, [np.hstack([x, 0.015 + 0 * x])], 0.02, Tuning())  # both within 0.015
    True
    >>> _keeps_ink(ink, [ink[0]], 0.02, Tuning())  # the other pass left out
    False
    >>> tick = np.array([[0.5, 0.0], [0.5, 0.03]])  # 3% long, a third of it left out
    >>> _keeps_ink(ink[:1] * 9 + [tick], [ink[0]], 0.02, Tuning())
    False
    """
    lines = [line for line in lines if len(line) >= 2]
    if not lines:
        return False
    reached = Reached.of(drawing, lines, reach, tuning.keep_reach / 8)
    return bool(1 - reached.near().mean() <= tuning.keep_left
                and 1 - reached.shares().min() <= tuning.keep_stroke)


__all__ = ["FILL_SAMPLES", "KEEP_EPSILON", "Prepared", "SimplifyResult",
           "build_complex", "from_record", "prepare", "simplify"]
