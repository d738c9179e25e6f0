"""What the pen stage's passes hand on (:mod:`core.lines`): one plain record, each pass
filling its own fields and returning a new record (``dataclasses.replace``)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..arrays.geometry import Segments
from ..arrays.polylines import resample_each, split
from ..complex.complex_state import ComplexState
from ..params import SimplifyParams, Tuning

__all__ = ["Line", "Work"]


@dataclass(frozen=True)
class Line:
    """One line of the drawing in the unit frame: an evenly spaced polyline (a closed one
    repeats its first point last), the pieces whose ink it stands for, and the line each
    end meets at a junction (an index into the same list of lines; None: a free end)."""

    points: np.ndarray
    closed: bool
    members: tuple[int, ...]
    meets: tuple[int | None, int | None] = (None, None)

    @cached_property
    def length(self) -> float:
        """Its length, measured when first asked for (the points are never changed in
        place: a pass makes a new line)."""
        d = np.diff(self.points, axis=0)
        return float(np.hypot(d[:, 0], d[:, 1]).sum())


@dataclass(frozen=True)
class Work:
    """The pen stage's state after some passes.

    Fields set at the start: the simplified complex, the params (resolved) and their
    tuning, d_eps, the sample spacing ``h`` (``tuning.sample`` d_eps), the input strokes
    (unit frame).
    Then, pass by pass: ``pieces`` and the input stroke and position within it of each
    (``pieces``); for every sample of every piece, the alive curve it follows and where
    along it, -1 and NaN where none (``follow``); the pairs of pieces that draw one line and
a group label per piece, their connected components (``group``);
    the lines (``fit``, ``corners``, ``junctions``); the fitted strokes and, per input
    stroke, the fitted stroke that draws most of it (``bezier``).
    """

    state: ComplexState
    params: SimplifyParams
    tuning: Tuning
    d: float
    h: float
    strokes: list[np.ndarray]
    memo: object = None
    pieces: list[np.ndarray] = field(default_factory=list)
    piece_stroke: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    piece_index: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    sample_curve: np.ndarray | None = None
    sample_at: np.ndarray | None = None
    labels: np.ndarray | None = None
    pairs: np.ndarray | None = None
    lines: list[Line] | None = None
    fitted: list = field(default_factory=list)
    groups: np.ndarray | None = None

    @classmethod
    def start(cls, state: ComplexState, params: SimplifyParams, strokes: list[np.ndarray],
              memo=None) -> Work:
        d = float(params.alpha)
        return cls(state, params, params.tuning, d, d * params.tuning.sample, strokes, memo)

    def with_(self, **changes) -> Work:
        return replace(self, **changes)

    def store(self, name: str):
        """The memo's store ``name`` (a :class:`core.curves.memo.StrokeMemo` field), shared
        by a result and its replays; without a memo, a dict of this call's own."""
        return {} if self.memo is None else getattr(self.memo, name)

    @property
    def meet_d(self) -> float:
        """The bundle width ends meet lines and overshoots are cut by (passes 7-9): d_eps,
        at least ``tuning.meet_alpha``."""
        return max(self.d, self.tuning.meet_alpha)

    @property
    def merged(self) -> bool:
        """Whether anything was simplified: at epsilon 0 each stroke stays as drawn."""
        return self.params.epsilon > 0

    @cached_property
    def ink(self) -> Segments:
        """Every piece's ink as chords about d_eps long (numbered by piece), for asking what
        other ink lies within a few bundle widths of a group's (a chord that long departs
        from a curve far less than that); made when first asked for, once per record."""
        points, sizes = resample_each(self.pieces, self.d)
        return Segments.of(split(points, sizes))

    def piece_sizes(self) -> np.ndarray:
        return np.fromiter(map(len, self.pieces), dtype=np.intp, count=len(self.pieces))

    def current_lines(self) -> list[Line]:
        """The lines so far; before ``fit``, each piece a line of its own."""
        if self.lines is not None:
            return self.lines
        return [Line(p, False, (k,)) for k, p in enumerate(self.pieces)]
