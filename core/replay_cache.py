"""Results kept to be replayed at other epsilons: what makes a slider (Blender's redo
panel re-running the operator on every change) cheap.

A sketch is simplified at the epsilon asked, and any smaller epsilon is then the replay of
a prefix of its merge history (``SimplifyResult.at``), which equals a fresh run exactly;
asked for a larger one, it runs once more, its merge loop on to the slider's top
(``simplify(..., cover=)``, the output made at the epsilon asked only), and every epsilon
of the slider replays from then on.
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from dataclasses import replace

import numpy as np

from .engine import Recorded, Simplified
from .params import EPSILON_SOFT_MAX, SimplifyParams
from .simplify import SimplifyResult, from_record, simplify
from .sketch import Sketch, Stroke

__all__ = ["COVERED_EPSILON", "OUTPUT_POINTS", "ReplayCache", "sketch_digest",
           "strokes_digest"]

#: the epsilon a run asked for above what is kept covers: the whole slider, so that only
#: the first step up runs again (with 0.03, every step above it ran from scratch: 30 s on
#: a 5,000-stroke drawing). A first run covers only its own epsilon: taken to 0.06 it
#: cost 1.26 times the core's run in Blender (docs/decisions.md)
COVERED_EPSILON = EPSILON_SOFT_MAX

#: output points kept for lookups (an epsilon already shown, for every drawing of a shot):
#: at most this many, over all kept outputs, the least recently used dropped first. With
#: their Beziers and attributes about 100 MB; a 13-keyframe shot of product sketches
#: shows about 25 epsilons of it
OUTPUT_POINTS = 4_000_000


def sketch_digest(sketch: Sketch) -> str:
    """A fingerprint of everything simplify reads from a sketch."""
    h = hashlib.blake2b(digest_size=16)
    for s in sketch.strokes:
        h.update(np.ascontiguousarray(s.points).tobytes())
        for extra in (s.width, s.pressure):
            h.update(b"-" if extra is None else np.ascontiguousarray(extra).tobytes())
        h.update(f"|{s.style}|{s.source_id}|{len(s.points)};".encode())
    return h.hexdigest()


def strokes_digest(strokes: list[Stroke]) -> str:
    """A fingerprint of output strokes: their points, Beziers and whether they close.

    >>> a = Stroke([[0, 0], [1, 0]])
    >>> strokes_digest([a]) == strokes_digest([Stroke([[0, 0], [1, 0]])]) != strokes_digest([])
    True
    """
    h = hashlib.blake2b(digest_size=16)
    for s in strokes:
        h.update(np.ascontiguousarray(s.points).tobytes())
        h.update(b"-" if s.bezier is None else np.ascontiguousarray(s.bezier).tobytes())
        h.update(f"|{s.closed}|{len(s.points)};".encode())
    return h.hexdigest()


class ReplayCache:
    """The last few simplify results, by sketch and by every parameter but epsilon, and
    the merge records of the last many runs made elsewhere (a pool's workers).

    Memory: a result holds its base complex, its ink and its output (tens of MB for a
    large drawing): ``size`` of them are kept. A record is the merges alone (about 1 KB a
    merge with a merged curve's points, a few MB for the largest sketches): ``records`` of
    them are kept, so that every drawing of a long shot replays (a redo panel's epsilon
    step then costs, per drawing, the base complex built again, the replay and the output
    stage; the merge loop is not run again). ``points``, when given, bounds the results
    kept by their sketches' ink points as well (a result with its line-stage memo takes
    about 1 KB a point): a :class:`core.parallel.KeptPool` worker's bound."""

    def __init__(self, size: int = 8, records: int = 512,
                 output_points: int = OUTPUT_POINTS, points: int | None = None) -> None:
        self.size = size
        self.records = records
        self.output_points = output_points
        self.points = points
        self.runs = 0  # how many times simplify actually ran
        self.rebuilds = 0  # how many results were rebuilt from a kept record
        self.dropped = 0  # how many results were dropped to keep within the bounds
        self._results: OrderedDict[tuple, SimplifyResult] = OrderedDict()
        self._result_points: dict[tuple, int] = {}
        self._records: OrderedDict[tuple, Recorded] = OrderedDict()
        self._outputs: OrderedDict[tuple, tuple[Simplified, int]] = OrderedDict()
        self._output_points = 0

    @staticmethod
    def _key(sketch: Sketch, params: SimplifyParams) -> tuple:
        return (sketch_digest(sketch), replace(params, epsilon=0.0))

    def remember(self, sketch: Sketch, params: SimplifyParams, recorded: Recorded) -> None:
        """Keep the record of a run of ``sketch`` at ``params`` made elsewhere."""
        key = self._key(sketch, params)
        self._records[key] = recorded
        self._records.move_to_end(key)
        while len(self._records) > self.records:
            self._records.popitem(last=False)

    def cover(self, sketch: Sketch, params: SimplifyParams) -> float:
        """How far a run of ``sketch`` at ``params`` should take its merge loop: the
        epsilon asked, the first time (a first press costs what the core does; a smaller
        epsilon then replays); the slider's top once an epsilon above what is kept is
        asked for (so that it runs again once, not at every step up)."""
        key = self._key(sketch, params)
        seen = key in self._results or key in self._records
        return max(params.epsilon, COVERED_EPSILON) if seen else params.epsilon

    def has_result(self, sketch: Sketch, params: SimplifyParams) -> bool:
        """Whether a kept result replays ``params.epsilon`` (here, cheaply)."""
        kept = self._results.get(self._key(sketch, params))
        return kept is not None and kept.covers >= params.epsilon

    def recorded(self, sketch: Sketch, params: SimplifyParams) -> Recorded | None:
        """The kept record that rebuilds ``params.epsilon`` (anywhere: a pool's worker
        too, :func:`core.parallel.simplify_all`'s ``records``), or None."""
        kept = self._records.get(self._key(sketch, params))
        return kept if kept is not None and kept.covers >= params.epsilon else None

    def result(self, sketch: Sketch, params: SimplifyParams, cover: float | None = None
               ) -> SimplifyResult:
        """The result ``simplify(sketch, params)`` gives, replayed from a cached run (or
        rebuilt from a kept record) when one covers ``params.epsilon``; otherwise run, its
        merge loop on to ``cover`` (by default :meth:`cover`'s)."""
        key = self._key(sketch, params)
        cached = self._results.get(key)
        recorded = self._records.get(key)
        if (cached is None or cached.covers < params.epsilon) and recorded is not None \
                and recorded.covers >= params.epsilon:
            self.rebuilds += 1
            cached = from_record(sketch, replace(recorded.params, epsilon=params.epsilon),
                                 list(recorded.merges), recorded.covers)
        elif cached is None or cached.covers < params.epsilon:
            self.runs += 1
            cached = simplify(sketch, params, cover=self.cover(sketch, params)
                              if cover is None else max(cover, params.epsilon))
        self._results[key] = cached
        self._results.move_to_end(key)
        self._result_points[key] = sum(len(s.points) for s in sketch.strokes)
        while len(self._results) > 1 and (
                len(self._results) > self.size or self.points is not None
                and sum(self._result_points.values()) > self.points):
            del self._result_points[self._results.popitem(last=False)[0]]
            self.dropped += 1
        return cached if cached.params.epsilon == params.epsilon else cached.at(params.epsilon)

    def output(self, sketch: Sketch, params: SimplifyParams, regions: bool
               ) -> Simplified | None:
        """The output kept for ``sketch`` at exactly ``params`` (epsilon too) and
        ``regions``, or None: a step back to an epsilon already shown is a lookup."""
        key = (sketch_digest(sketch), params, regions)
        kept = self._outputs.get(key)
        if kept is None:
            return None
        self._outputs.move_to_end(key)
        return kept[0]

    def keep_output(self, sketch: Sketch, params: SimplifyParams, regions: bool,
                    out: Simplified) -> None:
        """Keep ``out`` (without its record) for :meth:`output`, within
        :attr:`output_points` points over all kept outputs."""
        key = (sketch_digest(sketch), params, regions)
        points = sum(len(s.points) for s in out.strokes) + 1
        if key in self._outputs:
            self._output_points -= self._outputs.pop(key)[1]
        self._outputs[key] = (replace(out, record=None), points)
        self._output_points += points
        while self._output_points > self.output_points and len(self._outputs) > 1:
            self._output_points -= self._outputs.popitem(last=False)[1][1]

    def clear(self) -> None:
        """Forget everything kept (results, records, outputs)."""
        self._results.clear()
        self._result_points.clear()
        self._records.clear()
        self._outputs.clear()
        self._output_points = 0

    def strokes(self, sketch: Sketch, params: SimplifyParams) -> list[Stroke]:
        return self.result(sketch, params).strokes
