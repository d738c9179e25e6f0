"""Lines from the pen: the output stage that fits one line to each group of input strokes
the complex agglomeration says draw one line (paper 3.3, rethought).

The paper's agglomeration (3.2) decides, with its one epsilon, which ink is one line: a
merge keeps one curve where two ran side by side, or collapses the slender patch between
them. The complex's pieces are cut at every crossing, but the pen already drew each line
in one motion: so the lines are made from the input strokes, grouped by what the merges
kept, not chained from the pieces.

The passes, in order (each a module with one job; :data:`PASSES` names them):

1. ``pieces``: each input stroke resampled and cut where it turns sharply (a corner drawn
   in one motion is two lines; a small round shape, turning on beyond, is not; nor is a
   stroke another stroke lies along whole, a shape drawn round again): the pen strokes,
   the unit of grouping.
2. ``follow``: which alive curve of the simplified complex each sample of a piece runs
   along, and where along it.
3. ``group``: pieces that follow one alive curve along enough of their length (and
   overlap there) draw one line; groups are the connected components.
4. ``fit``: one centreline per group, fitted to all its pieces' ink at once (a spine
   grown from its longest piece, moved to the median offset of the ink in bins along
   it, then smoothed as a line); a piece that does not lie along the fitted line is split off.
5. ``join``: two lines of which the shorter lies along the longer are one line drawn
   twice: fitted again as one group.
6. ``absorb``: a short line lying wholly near a longer one (a hook, a crumb) is left out.
7. ``corners``: lines that consecutive pieces of one input stroke end at a corner join
   there again, the corner kept (the pen drew it in one motion).
8. ``orphans``: a stretch of a loose pass that parted from its line farther than a loose
   pass lies off the middle (the line's median followed the other passes there) is stood
   for by no line: it becomes a line of its own, drawn on from a free end where it
   carries one on.
9. ``junctions``: an end that stops near another line meets it exactly; an overshoot past
   a line is trimmed; lines that cross go straight through.
10. ``bezier``: each line smoothed between its corners and fitted with piecewise cubic
    Beziers.

Invariants: every pass is a function of the simplified complex, the input strokes and
the params alone, so a replay at a smaller epsilon gives exactly a fresh run's lines; a
pass named in ``params.skip`` is left out (``pieces`` and ``bezier`` cannot be: the first
makes the lines' ink, the last their curves). At epsilon 0 nothing merged, every piece is
its own group, and each input stroke comes back whole, fitted.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..complex.complex_state import ComplexState
from ..params import SimplifyParams
from ..sketch import SketchError
from . import absorb, bezier, corners, fit, follow, group, join, junctions, orphans, pieces
from .work import Work

__all__ = ["PASSES", "PenRun", "lines_from_pen"]

#: the passes in order: (name, function of the work so far)
PASSES: tuple[tuple[str, Callable[[Work], Work]], ...] = (
    ("pieces", pieces.run),
    ("follow", follow.run),
    ("group", group.run),
    ("fit", fit.run),
    ("join", join.run),
    ("absorb", absorb.run),
    ("corners", corners.run),
    ("orphans", orphans.run),
    ("junctions", junctions.run),
    ("bezier", bezier.run),
)
_REQUIRED = ("pieces", "bezier")


@dataclass
class PenRun:
    """What the pen stage made: the work after its last pass, and seconds per pass."""

    work: Work
    seconds: dict[str, float] = field(default_factory=dict)


def lines_from_pen(state: ComplexState, params: SimplifyParams, strokes: list[np.ndarray],
                   memo=None, picture: Callable[[str, Work], None] | None = None) -> PenRun:
    """Run the passes on a simplified complex.

    Args:
        state: the complex after the merge loop (unit frame).
        params: the resolved params (:class:`core.params.ResolvedParams`).
        strokes: the input strokes in the unit frame, as cleaned.
        memo: a :class:`core.curves.memo.StrokeMemo` whose Bezier fits a replay reuses.
        picture: called with each pass's name and the work after it (debug pictures).

    Returns:
        A :class:`PenRun`; its ``work.fitted`` are the output strokes.
    """
    unknown = sorted(set(params.skip) - {name for name, _ in PASSES})
    if unknown:
        raise SketchError(f"unknown pass to skip: {', '.join(unknown)} (the passes: "
                          f"{', '.join(name for name, _ in PASSES)})")
    fixed = sorted(set(params.skip) & set(_REQUIRED))
    if fixed:
        raise SketchError(f"the pass {', '.join(fixed)} cannot be skipped")
    work = Work.start(state, params, strokes, memo)
    seconds = {}
    for name, run in PASSES:
        if name in params.skip:
            continue
        t0 = time.perf_counter()
        work = run(work)
        seconds[name] = time.perf_counter() - t0
        if picture is not None:
            picture(name, work)
    return PenRun(work, seconds)
