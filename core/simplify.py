"""The public entry point: ``simplify(sketch, params) -> SimplifyResult``."""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np
import shapely

from .arrays.geometry import polygons_from
from .complex.base_complex import BaseComplex, build_base_complex
from .complex.complex_state import ComplexState, Merge
from .complex.noding import more_crossings_than
from .io.cleaning import (
    CleaningReport,
    Normalisation,
    clean_sketch,
    drawing_strokes,
    normalised_strokes,
)
from .merge.agglomeration import AgglomerationStats, agglomerate
from .output.attributes import NearestInk
from .output.memo import StrokeMemo
from .output.to_strokes import to_strokes
from .params import SimplifyParams
from .sketch import Region, Sketch, SketchError, Stroke

#: regions smaller than this share of the drawing's box are slivers between close lines,
#: not regions to fill
FILL_MIN_SHARE = 1e-3


@dataclass
class SimplifyResult:
    """Output strokes (input coordinates) and everything that led to them."""

    strokes: list[Stroke]
    params: SimplifyParams
    complex: BaseComplex  # the initial base complex, unit frame
    state: ComplexState  # the simplified complex: alive curves and patches
    history: list[Merge]  # every merge applied, in order, with its cost
    normalisation: Normalisation
    cleaning: CleaningReport
    counts: dict[str, dict[str, int]]
    timings: dict[str, float]
    stats: AgglomerationStats | None = None
    _input: Sketch | None = field(default=None, repr=False)
    _ink: NearestInk | None = field(default=None, repr=False)
    _memo: StrokeMemo = field(default_factory=StrokeMemo, repr=False)  # shared by .at()

    @property
    def bundle_width(self) -> float:
        """The bundle width used, d_eps = alpha * D, in the sketch's own units."""
        return self.params.alpha * self.normalisation.scale

    def to_sketch(self) -> Sketch:
        src = self._input
        return Sketch(list(self.strokes), src.width if src else None,
                      src.height if src else None)

    def at(self, epsilon: float) -> SimplifyResult:
        """The result ``simplify`` gives with a smaller ``epsilon``, by replaying history."""
        if not 0 <= epsilon <= self.params.epsilon:
            raise SketchError(f"epsilon {epsilon} is outside 0..{self.params.epsilon}, the "
                              "range this result's merge history covers")
        t0 = time.perf_counter()
        state = ComplexState(self.complex)
        for merge in self.history:
            if merge.cost >= epsilon or state.targets_reached(self.params.target_patches,
                                                              self.params.target_curves):
                break
            state.apply(merge)
        params = replace(self.params, epsilon=epsilon)
        history = self.history[:state.merges_applied]
        timings = {"replay": time.perf_counter() - t0}
        return _finish(self._input, self._ink, self.cleaning, self.normalisation, self.complex,
                       state, history, params, None, timings, self._memo)

    def fill_regions(self, min_share: float = FILL_MIN_SHARE) -> list[Region]:
        """The closed regions of the simplified drawing as plain rings (input coordinates),
        largest first, leaving out slivers smaller than ``min_share`` of the area of the
        drawing's box: what a fill is drawn from. A region inside another is the other's
        hole and a region of its own, after it (so that a fill drawn in this order, holes
        cut out, leaves the inner fill whole)."""
        smallest = min_share * 0.5 * self.normalisation.scale ** 2  # box of diagonal D
        parts = [part for poly in self.regions() for part in shapely.get_parts(poly)
                 if part.area >= smallest]
        parts.sort(key=lambda part: -part.area)

        def ring(r) -> np.ndarray:
            return np.asarray(r.coords)[:-1]

        return [Region(ring(part.exterior), tuple(ring(h) for h in part.interiors
                                                  if shapely.Polygon(h).area >= smallest))
                for part in parts]

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


def _finish(sketch: Sketch, ink: NearestInk, cleaning: CleaningReport, norm: Normalisation,
            cx: BaseComplex, state: ComplexState, history: list[Merge],
            params: SimplifyParams, stats: AgglomerationStats | None,
            timings: dict[str, float], memo: StrokeMemo | None = None) -> SimplifyResult:
    t0 = time.perf_counter()
    memo = StrokeMemo() if memo is None else memo
    fitted = to_strokes(state, params, memo, ink)
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
    return SimplifyResult(strokes, params, cx, state, history, norm, cleaning, counts, timings,
                          stats, sketch, ink, memo)


def simplify(sketch: Sketch, params: SimplifyParams | None = None) -> SimplifyResult:
    """Simplify a rough sketch into few long smooth strokes.

    Raises :class:`SketchError` for input that cannot be a sketch or bad parameters.
    """
    params = params if params is not None else SimplifyParams()
    if not isinstance(params, SimplifyParams):
        raise SketchError(f"params must be SimplifyParams, got {type(params).__name__}")
    t0 = time.perf_counter()
    cleaned, report = clean_sketch(sketch)
    unit, norm = normalised_strokes(cleaned)
    params = params.resolved(drawing_strokes(unit))  # "auto" alpha follows the ink
    t1 = time.perf_counter()
    if params.max_curves is not None:
        crossings = more_crossings_than(unit, params.max_curves // 2)
        if crossings is not None:
            raise SketchError(f"the strokes cross each other over {crossings} times, too "
                              f"tangled for max_curves = {params.max_curves}: simplify it "
                              "in parts")
    cx = build_base_complex(unit)
    if params.max_curves is not None and cx.num_curves > params.max_curves:
        raise SketchError(f"the strokes cross into {cx.num_curves} curves, more than the "
                          f"{params.max_curves} allowed (max_curves): simplify it in parts")
    t2 = time.perf_counter()
    history, state, stats = agglomerate(cx, params)
    t3 = time.perf_counter()
    ink = NearestInk(cleaned.strokes, unit)
    timings = {"clean": t1 - t0, "complex": t2 - t1, "agglomerate": t3 - t2}
    result = _finish(cleaned, ink, report, norm, cx, state, history, params, stats, timings)
    result.timings["total"] = time.perf_counter() - t0
    return result


__all__ = ["FILL_MIN_SHARE", "SimplifyResult", "simplify"]
