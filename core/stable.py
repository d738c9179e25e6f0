"""Stable lines across frames: a keyframe's result held to the one before where the drawing
did not change.

Simplified one by one, slightly redrawn keyframes of one drawing (jitter of half a pixel)
come out with the same lines placed within a fraction of a pixel of each other, but cut and
joined differently: 6 to 10 strokes for the house sample over five jittered copies, which
an animator sees boil. Walking the keyframes in order, each result is held to the one
before: a stroke of the previous result is kept as it is where the new result still runs
along it (all but ``MISSED`` of it within the bundle width), and a new stroke is added
only where the kept ones do not already draw it (less than ``HELD`` of it within the width).
Where the drawing changed, the new result's strokes take over.

Invariants: a result held to itself is itself; every kept stroke lies within the bundle
width of the new result, so nothing is drawn where the new keyframe has no line.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .arrays.geometry import Reached
from .sketch import Stroke

__all__ = ["HELD", "MISSED", "held_to"]

#: a previous stroke with more than this share of it off the new result is not kept
MISSED = 0.05
#: a new stroke with at least this share of it on the kept strokes is drawn by them
HELD = 0.5


def _near(strokes: list[Stroke], others: list[Stroke], width: float
          ) -> tuple[np.ndarray, list[set[int]]]:
    """For each stroke: the share of it within ``width`` of the ``others``, and which of
    them it comes within ``width`` of."""
    touched: list[set[int]] = [set() for _ in strokes]
    if not strokes or not others:
        return np.zeros(len(strokes)), touched
    reached = Reached.of([s.points for s in strokes], [o.points for o in others], width,
                         width / 2)
    for k, o in zip(reached.polyline[reached.sample].tolist(), reached.line.tolist()):
        touched[k].add(o)
    return reached.shares(), touched


def held_to(previous: list[Stroke], current: list[Stroke], width: float) -> list[Stroke]:
    """``current`` held to ``previous`` (see the module docstring): the previous strokes the
    current result still draws, then the current strokes they do not. A kept stroke takes
    its source ids from the current strokes along it, so that they name strokes of the
    current keyframe's input.

    >>> line = Stroke(np.array([[0.0, 0.0], [10.0, 0.0]]))
    >>> moved = Stroke(np.array([[0.0, 0.1], [10.0, 0.1]]), sources=(3,))
    >>> [s.points[0, 1] for s in held_to([line], [moved], 0.5)]  # held
    [0.0]
    >>> [s.points[0, 1] for s in held_to([line], [Stroke(moved.points + [0, 2])], 0.5)]
    [2.1]
    """
    if not previous or not current or not width > 0:
        return list(current)
    on_current, along = _near(previous, current, width)
    kept = [replace(p, sources=tuple(sorted({i for c in near for i in current[c].sources})))
            for p, share, near in zip(previous, on_current, along) if share >= 1 - MISSED]
    on_kept, _ = _near(current, kept, width)
    return kept + [c for c, share in zip(current, on_kept) if share < HELD]
