"""Stable lines across frames: a keyframe's result held to the one before where the drawing
did not change, and carried along where it moved.

Simplified one by one, slightly redrawn keyframes of one drawing (jitter of half a pixel)
come out with the same lines placed within a fraction of a pixel of each other, but cut and
joined differently: 6 to 10 strokes for the house sample over five jittered copies, which
an animator sees boil. Walking the keyframes in order, each result is held to the one
before: a stroke of the previous result is kept where the new result still runs along it
(all but ``MISSED`` of it within the bundle width), and a new stroke is added only where
the kept ones do not already draw it (less than ``HELD`` of it within the width). Where
the drawing changed, the new result's strokes take over.

A drawing that moves, turns or is redrawn a little from key to key (an animation) would
leave a kept stroke behind its ink, up to the bundle width, before the new result took
over: so a kept stroke is carried onto the new result's lines (:func:`carried`). The
motion is a turn and a shift fitted to where the kept strokes' points
meet the new lines running along them, first for all of them at once (a drawing moved
whole: a straight stroke alone cannot say how far it slid along itself), then for each
stroke on top (a part moved on its own). Redrawn in place, a result's lines move a little
from key to key without the drawing moving: so the whole drawing is moved only where its
motion exceeds ``STILL`` of the width, and a stroke on its own only where its own exceeds
``PART`` and brings it nearer the keyframe's ink than the whole drawing's motion does (a
result may place a line elsewhere within the same ink: the ink says whether that part
moved); otherwise a kept stroke stays exactly where it was, and does not boil.

Given the keyframe's ink, a previous stroke is kept where the ink still runs along it
(the drawing did not change there), though the keyframe's own result dropped or shortened
that line: redrawn from key to key, results do, and the held lines would flicker.

Invariants: a result held to itself is itself; every kept stroke lies within the bundle
width of the new keyframe's ink (or, without it, of its result), so nothing is drawn where
the new keyframe has no ink.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from .arrays.geometry import Reached, Segments, nearest_of_each, tangents_each
from .arrays.polylines import resample_polyline
from .sketch import Stroke

__all__ = ["DAMPING", "HELD", "MISSED", "PART", "ROUNDS", "RUNNING_COS", "SPACING", "STILL",
           "Carried", "Motion", "carried", "held_to", "motion_onto"]

#: a previous stroke with more than this share of it off the new result is not kept
MISSED = 0.05
#: a new stroke with at least this share of it on the kept strokes is drawn by them
HELD = 0.5
#: the kept strokes stay where they were unless the drawing moved more than this share
#: of the bundle width on average: the lag this leaves is at most this, under 0.1% of the
#: diagonal at the usual widths (alpha 0.012 to 0.015), and redrawn in place the fit
#: of the whole drawing's motion moves about a twentieth of the width (scripts/bench_stable.py)
STILL = 0.075
#: ... and a stroke moves on its own, on top, only where its own motion differs by more
#: than this (and the ink agrees, see the module): redrawn in place, most single strokes'
#: fits move up to a fifth of the width
PART = 0.25
#: a new stroke's point is drawn by a kept stroke that runs along it: |cos| at least this
RUNNING_COS = 0.9
#: strokes are sampled every this share of the bundle width, for the motions' fits and
#: for the shares within the width: a rigid motion is found to well under the width from
#: two samples a width, and a share counted to a few percent of a stroke
SPACING = 0.5
#: fits of the motion, each from where the last took the strokes: a drawing moved about the
#: bundle width in a key is followed to within a hundredth of it in three
ROUNDS = 3
#: a way of moving that the lines show less than this share of what a line square to it
#: shows is damped away (:func:`motion_onto`)
DAMPING = 0.01


def _lines(strokes: list[Stroke]) -> tuple[list[int], Segments | None]:
    """The strokes that are lines (a dot is none), and their segments (None if none)."""
    lines = [k for k, s in enumerate(strokes) if len(s.points) >= 2]
    return lines, Segments.of([strokes[k].points for k in lines]) if lines else None


def _near(strokes: list[Stroke], others: list[Stroke], width: float,
          lines: tuple[list[int], Segments | None] | None = None
          ) -> tuple[np.ndarray, list[set[int]]]:
    """For each stroke: the share of it within ``width`` of the ``others``, and which of
    them it comes within ``width`` of. ``lines``: the others' :func:`_lines`, where the
    caller has them (their segment tree is kept with them)."""
    touched: list[set[int]] = [set() for _ in strokes]
    lines, segments = _lines(others) if lines is None else lines
    if not strokes or segments is None:
        return np.zeros(len(strokes)), touched
    reached = Reached.of([s.points for s in strokes], segments, width, SPACING * width)
    for k, o in zip(reached.polyline[reached.sample].tolist(), reached.line.tolist()):
        touched[k].add(lines[o])
    return reached.shares(), touched


@dataclass(frozen=True)
class Motion:
    """A rigid map ``p -> turn @ p + shift``."""

    turn: np.ndarray  #: (2, 2) a rotation
    shift: np.ndarray  #: (2,)

    def __call__(self, points: np.ndarray) -> np.ndarray:
        return points @ self.turn.T + self.shift

    def then(self, other: Motion) -> Motion:
        """``other`` after this one."""
        return Motion(other.turn @ self.turn, other.turn @ self.shift + other.shift)


STILLNESS = Motion(np.eye(2), np.zeros(2))


def motion_onto(points: np.ndarray, feet: np.ndarray, normal: np.ndarray) -> Motion:
    """The small turn and shift that take ``points`` onto the lines through their ``feet``
    square to ``normal`` (unit rows), in least squares: ICP's point-to-line step, which
    follows a line sliding along itself no further than its ends show, where fitting
    points to their feet would drag every step back.

    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> normal = np.array([[0.0, 1.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]])
    >>> m = motion_onto(square, square + [0.1, 0.2], normal)
    >>> m.shift.round(2).tolist(), bool(np.allclose(m.turn, np.eye(2)))  # damped a little
    ([0.1, 0.2], True)
    """
    middle = points.mean(axis=0)
    q = points - middle
    size = max(float(np.sqrt((q * q).sum(axis=1).mean())), 1e-300)  # the turn's lever
    rows = np.column_stack([(normal[:, 1] * q[:, 0] - normal[:, 0] * q[:, 1]) / size,
                            normal])
    miss = ((feet - points) * normal).sum(axis=1)
    # damped (Levenberg): where the lines say little of a way of moving (a straight
    # stroke sliding along itself, a gentle curve nearly so), it stays put; without this
    # a nearly straight stroke of the house sample slid 28 px on noise
    damp = np.sqrt(DAMPING * len(points)) * np.eye(3)
    (lever, dx, dy), *_ = np.linalg.lstsq(np.vstack([rows, damp]),
                                          np.r_[miss, np.zeros(3)], rcond=None)
    angle = lever / size
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return Motion(turn, middle - turn @ middle + np.array([dx, dy]))


def _feet(points: np.ndarray, tangent: np.ndarray, lines: Segments, reach: float
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Which of the evenly spaced ``points`` (polylines end to end, with their ``tangent``,
    :func:`tangents_each`) have a line of ``lines`` running along them within ``reach``;
    the nearest point of such a line to each of them, and that line's unit normal there.
    One tree query for them all."""
    i, seg = lines.running_along(points, tangent, reach, RUNNING_COS)
    if not len(i):
        return np.zeros(0, dtype=np.intp), np.zeros((0, 2)), np.zeros((0, 2))
    foot = lines.foot(seg, lines.along(seg, points[i]))
    first = nearest_of_each(i, np.hypot(*(foot - points[i]).T), np.arange(len(i)))
    v = lines.vector[seg[first]]
    normal = np.column_stack([-v[:, 1], v[:, 0]]) / np.hypot(v[:, 0], v[:, 1])[:, None]
    return i[first], foot[first], normal


def _fitted(groups: list[list[np.ndarray]], lines: Segments, reach: float,
            starts: list[Motion], rounds: int) -> list[Motion]:
    """For each group of polylines: its ``start``, then the motion that takes its points
    onto the ``lines`` running along them (:func:`motion_onto`), refined ``rounds`` times
    from where the last one took them (as ICP does); the matches farther than three times
    the median are left out of each step (a point whose nearest line along it is another
    line's). The groups are fitted apart, their points matched in one query a round."""
    motions = list(starts)
    active = list(range(len(groups)))
    for _ in range(rounds):
        if not active:
            break
        moved = [[motions[g](p) for p in groups[g]] for g in active]
        sizes = [sum(map(len, m)) for m in moved]
        parts = [p for m in moved for p in m]
        flat = np.concatenate(parts)
        i, foot, normal = _feet(flat, tangents_each(parts), lines, reach)
        cuts = np.searchsorted(i, np.cumsum(sizes)[:-1])
        still = []
        for g, mine, dst, nrm in zip(active, np.split(i, cuts), np.split(foot, cuts),
                                     np.split(normal, cuts)):
            if len(mine) < 3:
                continue
            src = flat[mine]
            miss = np.abs(((dst - src) * nrm).sum(axis=1))
            fair = miss <= 3 * max(float(np.median(miss)), 1e-12 * reach)
            motions[g] = motions[g].then(motion_onto(src[fair], dst[fair], nrm[fair]))
            still.append(g)
        active = still
    return motions


def carried(strokes: list[Stroke], current: list[Stroke], width: float,
            support: list[Stroke] | None = None) -> list[Stroke]:
    """The ``strokes`` (the keyframe before's) carried onto the ``current`` lines (see the
    module): moved by the motion that fits them all, then each by its own on top where the
    lines run along most of it; one moved less than ``STILL`` of ``width`` on average
    stays as it was, and so does one the motion would take farther off the ``support``
    (the keyframe's ink, or by default the ``current`` lines). Points and Bezier control
    points move together; widths, pressures and colours stay.

    >>> line = Stroke(np.array([[0.0, 0.0], [5.0, 5.0], [10.0, 0.0]]))
    >>> moved = Stroke(line.points + [0.3, 0.2])
    >>> carried([line], [moved], 1.0)[0].points.round(3).tolist()
    [[0.3, 0.2], [5.3, 5.2], [10.3, 0.2]]
    >>> carried([line], [Stroke(line.points + [0.01, 0.0])], 1.0)[0] is line  # still
    True
    """
    return _carried(strokes, current, width, support).strokes


class Carried(NamedTuple):
    """Strokes carried onto a keyframe's lines (:func:`carried`), and where they now lie."""

    strokes: list[Stroke]
    shares: np.ndarray  #: the share of each within the width of the support
    near: list[set[int]]  #: the support's strokes each comes within the width of


def _carried(strokes: list[Stroke], current: list[Stroke], width: float,
             support: list[Stroke] | None) -> Carried:
    lines = _lines(current)  # dots say nothing of where a line is
    drawn = lines if support is None else _lines(support)
    support = current if support is None else support
    segs = lines[1]
    if not strokes or segs is None:
        return Carried(list(strokes), *_near(strokes, support, width, drawn))
    points = [resample_polyline(s.points, SPACING * width) for s in strokes]
    whole, = _fitted([points], segs, width, [STILLNESS], ROUNDS)
    flat = np.concatenate(points)
    if np.mean(np.hypot(*(whole(flat) - flat).T)) < STILL * width:
        whole = STILLNESS
    ink = drawn[1]
    # its own motion only where the new lines run along most of it (a stroke the new
    # result lacks is not pulled by the lines that merely meet its ends), and where it
    # brings the stroke nearer the ink than the whole drawing's motion does: a line the
    # keyframe's result placed elsewhere in the same ink is no motion of the drawing
    by_whole = [whole(p) for p in points]
    sizes = np.fromiter(map(len, points), dtype=np.intp, count=len(points))
    found = _feet(np.concatenate(by_whole), tangents_each(by_whole), segs, width)[0]
    along = np.bincount(np.repeat(np.arange(len(points)), sizes)[found],
                        minlength=len(points))
    alone = [k for k in range(len(points)) if 2 * along[k] >= sizes[k]]
    own = [whole] * len(points)
    for k, motion in zip(alone, _fitted([[points[k]] for k in alone], segs, width,
                                        [whole] * len(alone), ROUNDS)):
        own[k] = motion
    by_own = [m(p) for m, p in zip(own, points)]
    far = [k for k in range(len(points))
           if np.mean(np.hypot(*(by_own[k] - by_whole[k]).T)) >= PART * width]
    nearer = set(far)
    if ink is not None and far:
        cuts = np.cumsum(sizes[far])[:-1]
        mine = np.split(ink.distance(np.concatenate([by_own[k] for k in far])), cuts)
        theirs = np.split(ink.distance(np.concatenate([by_whole[k] for k in far])), cuts)
        nearer = {k for k, a, b in zip(far, mine, theirs) if a.mean() < b.mean()}
    out = []
    for k, stroke in enumerate(strokes):
        motion = own[k] if k in nearer else whole
        if motion is STILLNESS:
            out.append(stroke)
            continue
        out.append(replace(stroke, points=motion(stroke.points),
                           bezier=None if stroke.bezier is None else motion(stroke.bezier)))
    # a stroke the fit took farther off what holds it (matched to the wrong lines) stays
    # as it was
    before, before_near = _near(strokes, support, width, drawn)
    after, after_near = before.copy(), list(before_near)  # a stroke left still: as before
    went = [k for k, (m, s) in enumerate(zip(out, strokes)) if m is not s]
    if went:
        after[went], near = _near([out[k] for k in went], support, width, drawn)
        for k, n in zip(went, near):
            after_near[k] = n
    moved = after >= before
    return Carried([m if ok else s for m, s, ok in zip(out, strokes, moved)],
                   np.where(moved, after, before),
                   [a if ok else b for a, b, ok in zip(after_near, before_near, moved)])


def held_to(previous: list[Stroke], current: list[Stroke], width: float,
            ink: list[Stroke] | None = None) -> list[Stroke]:
    """``current`` held to ``previous`` (see the module docstring): the previous strokes the
    keyframe still draws, carried onto its lines (:func:`carried`), then the current
    strokes they do not draw.

    Args:
        previous: the held result of the keyframe before.
        current: this keyframe's result.
        width: the bundle width.
        ink: this keyframe's input strokes. Given, a previous stroke is kept where the
            keyframe's ink still runs along it, whatever its result did there: redrawn,
            a result may drop a line or end it shorter in one key and not the next (the
            lamp's 31 to 43 strokes, held to their results, 37 to 43), where the ink
            says nothing changed. Not given, where its result still does.

    Returns:
        The held strokes. A kept stroke takes its source ids from the ink along it, or the
        current strokes along it, so that they name strokes of this keyframe's input.

    >>> line = Stroke(np.array([[0.0, 0.0], [10.0, 0.0]]))
    >>> redrawn = Stroke(np.array([[0.0, 0.01], [10.0, 0.01]]), sources=(3,))
    >>> [s.points[0, 1] for s in held_to([line], [redrawn], 0.5)]  # held where it was
    [0.0]
    >>> [round(s.points[0, 1], 6) for s in held_to([line], [Stroke(line.points + [0, 0.2])],
    ...                                            0.5)]  # carried along
    [0.2]
    >>> [s.points[0, 1] for s in held_to([line], [Stroke(redrawn.points + [0, 2])], 0.5)]
    [2.01]
    >>> short = Stroke(redrawn.points * [0.5, 1])  # the result ends it at 5, the ink at 10
    >>> [len(held_to([line], [short], 0.5)), len(held_to([line], [short], 0.5, [line]))]
    [1, 1]
    >>> held_to([line], [short], 0.5, [line])[0].points[-1].tolist()  # the line, held
    [10.0, 0.0]
    """
    if not previous or not current or not width > 0:
        return list(current)
    if ink is None:
        support, ids = current, [c.sources for c in current]
    else:
        support = ink
        ids = [(s.source_id if s.source_id is not None else k,) for k, s in enumerate(ink)]
    # carried first, then judged where they now lie: a drawing moved by most of the width
    # in a key, redrawn, would leave too much of a stroke off its own ink to be kept
    moved = _carried(previous, current, width, support)
    kept = [replace(m, sources=tuple(sorted({i for c in near for i in ids[c]})))
            for m, share, near in zip(moved.strokes, moved.shares, moved.near)
            if share >= 1 - MISSED]
    on_kept, _ = _near(current, kept, width)
    return kept + [c for c, share in zip(current, on_kept) if share < HELD]
