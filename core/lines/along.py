"""How one polyline runs along another: two strokes each lying along the other whole are
passes of one line (pass 1); the share of a piece that lies along a line, and whether it
leaves the line from the line's middle; two pieces that run along each other and then
part, both going on, are passes of two lines (pass 4).
"""

from __future__ import annotations

import numpy as np

from ..arrays.geometry import Reached, project_on
from ..arrays.polylines import arc_lengths

__all__ = ["parting", "runs_along", "twinned"]


def twinned(polylines: list[np.ndarray], of: np.ndarray, reach: float, share: float,
            spacing: float) -> np.ndarray:
    """Whether each of the polylines numbered ``of`` has a twin among ``polylines``:
    another that it lies along and that lies along it, passes of one line: at least
    ``share`` of each one's samples (every ``spacing``) within ``reach`` of the other as
    drawn (pass 1). A short pass along part of a long one is not a twin of it; two lines
    drawn once each, closer than ``reach`` all along, are (the reach is the bundle's own
    width). Only the polylines of ``of`` are sampled against all, and all against those of
    ``of``: the others' twins are not sought.

    >>> x = np.linspace(0, 1, 21)[:, None]
    >>> a, b, c = np.hstack([x, 0 * x]), np.hstack([x, 0.01 + 0 * x]), np.hstack([x / 2, x])
    >>> twinned([a, b, c], np.array([0, 2]), 0.02, 0.8, 0.05).tolist()  # c crosses a and b
    [True, False]
    >>> twinned([a, b[:8]], np.array([0, 1]), 0.02, 0.8, 0.05).tolist()  # b along a third of a
    [False, False]
    """
    n = len(polylines)
    of = np.asarray(of, dtype=np.intp)
    if n < 2 or not len(of):
        return np.zeros(len(of), dtype=bool)
    chosen = [polylines[k] for k in of.tolist()]
    # "a lies along b", keyed a * n + b: ``of`` against all, then all against ``of``
    own, other = _along(chosen, polylines, reach, share, spacing)
    ahead = of[own].astype(np.int64) * n + other
    own, other = _along(polylines, chosen, reach, share, spacing)
    back = of[other].astype(np.int64) * n + own  # the other lies along one of ``of``
    both = np.intersect1d(ahead, back)
    both = both[both // n != both % n]  # not itself
    return np.isin(of, both // n)


def _along(polylines: list[np.ndarray], lines: list[np.ndarray], reach: float, share: float,
           spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """The pairs (polyline, line), indices into each, with at least ``share`` of the
    polyline's samples (every ``spacing``) within ``reach`` of the line: each sample
    counted once for each line it lies within reach of."""
    reached = Reached.of(polylines, lines, reach, spacing)
    m = len(lines)
    key = np.unique(reached.sample.astype(np.int64) * m + reached.line)
    pair, counts = np.unique(reached.polyline[key // m].astype(np.int64) * m + key % m,
                             return_counts=True)
    enough = counts / np.maximum(reached.count[pair // m], 1) >= share
    return (pair[enough] // m).astype(np.intp), (pair[enough] % m).astype(np.intp)


def runs_along(line: np.ndarray, pieces: list[np.ndarray], reach: float,
               least: float, closed: bool) -> tuple[np.ndarray, np.ndarray]:
    """The share of each piece within ``reach`` of ``line``, and whether each leaves it:
    runs along it and then, from where the line goes on for at least ``least`` (arc
    length) either way, away from it to the piece's own end, farther than ``reach`` along
    at least ``least``. A ring is left by none.

    >>> x = np.linspace(0, 1, 41)[:, None]
    >>> line = np.hstack([x, 0 * x])
    >>> on = np.hstack([x, 0 * x + 0.01])
    >>> off = np.hstack([0.5 * x, np.maximum(0, x - 0.5)])  # along to 0.25, then away
    >>> share, leaves = runs_along(line, [on, off], 0.02, 0.1, False)
    >>> share.round(2).tolist(), leaves.tolist()
    ([1.0, 0.51], [False, True])
    """
    sizes = np.fromiter(map(len, pieces), dtype=np.intp, count=len(pieces))
    firsts = np.cumsum(sizes) - sizes
    lasts = firsts + sizes - 1
    ink = np.concatenate(pieces)
    along = project_on(line, ink)
    near = along.distance <= reach
    share = np.add.reduceat(near.astype(np.intp), firsts) / sizes
    if closed:
        return share, np.zeros(len(pieces), bool)
    # each piece's first and last sample near the line (every piece with none is not
    # left: it never ran along), and how far the piece goes on past them to its ends
    index = np.arange(len(ink))
    first_near = np.minimum.reduceat(np.where(near, index, len(ink)), firsts)
    last_near = np.maximum.reduceat(np.where(near, index, -1), firsts)
    ran = share > 0
    first_near, last_near = np.where(ran, first_near, firsts), np.where(ran, last_near, lasts)
    s = arc_lengths(ink, firsts, lasts)
    leaves = np.zeros(len(pieces), bool)
    for gone, where in ((s[lasts] - s[last_near], along.at[last_near]),
                        (s[first_near], along.at[first_near])):
        leaves |= ran & (gone >= least) & (least <= where) & (where <= along.length - least)
    return share, leaves


def parting(pieces: list[np.ndarray], pairs: np.ndarray, reach: float, least: float
            ) -> np.ndarray:
    """For each of ``pairs`` (indices into ``pieces``), whether its two pieces run along
    each other and then part, each going on: one leaves the other from the other's middle
    (:func:`runs_along`, at ``reach`` and ``least``). Two passes of one line end near
    where the line ends, or run on together; two close lines that part somewhere (a
    narrow fork, an edge running along another for a while) are told apart there,
    however their passes interleave along the stretch they share. But not where the
    heading along either spans more than half a turn: passes of a curl or a loop drawn
    loosely wind in at their own rates, and part no more than a ring's passes do.

    >>> x = np.linspace(0, 1, 41)[:, None]
    >>> edge = np.hstack([x, 0 * x])
    >>> again = np.hstack([0.45 * x, 0 * x + 0.01])  # a shorter pass, ending before the fork
    >>> fork = np.hstack([x, np.maximum(0, x - 0.5)])  # along to 0.5, then away
    >>> parting([edge, again, fork], np.array([[0, 1], [0, 2], [1, 2]]), 0.02, 0.1).tolist()
    [False, True, False]
    >>> t = np.linspace(0, 1.5 * np.pi, 120)[1:]  # a curl drawn twice, the second tighter
    >>> curls = [np.vstack([np.hstack([0.5 * x, 0 * x]), np.c_[0.5 + r * np.sin(t),
    ...          0.15 - r * np.cos(t)]]) for r in (0.15 + 0 * t, 0.15 * np.exp(-0.5 * t))]
    >>> parting(curls, np.array([[0, 1]]), 0.02, 0.1).tolist()
    [False]
    >>> bool(runs_along(curls[0], curls[1:], 0.02, 0.1, False)[1][0])  # though it leaves
    True
    """
    gone = np.zeros(len(pairs), bool)
    if not len(pairs):
        return gone
    curls = np.array([_spans_half_a_turn(p) for p in pieces])
    judged = ~(curls[pairs[:, 0]] | curls[pairs[:, 1]])
    if not judged.any():
        return gone
    both = np.concatenate([pairs[judged], pairs[judged][:, ::-1]])  # (line, piece): the
    which = np.concatenate([np.flatnonzero(judged)] * 2)  # piece along the line
    order = np.argsort(both[:, 0], kind="stable")
    both, which = both[order], which[order]
    bounds = np.flatnonzero(np.r_[True, both[1:, 0] != both[:-1, 0], True])
    for a, b in zip(bounds[:-1], bounds[1:]):
        line = pieces[both[a, 0]]
        if len(line) < 2:
            continue
        leaves = runs_along(line, [pieces[k] for k in both[a:b, 1]], reach, least, False)[1]
        gone[which[a:b][leaves]] = True
    return gone


def _spans_half_a_turn(piece: np.ndarray) -> bool:
    """Whether the heading along ``piece`` spans more than half a turn.

    >>> t = np.linspace(0, 1.2 * np.pi, 30)
    >>> _spans_half_a_turn(np.c_[np.cos(t), np.sin(t)]), _spans_half_a_turn(np.c_[t, t])
    (True, False)
    """
    d = np.diff(piece, axis=0)
    if len(d) < 2:
        return False
    heading = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    return bool(np.ptp(heading) > np.pi)
