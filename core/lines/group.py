"""Pass 3 of :mod:`core.lines`: which pieces draw one line. Two pieces that follow the same
alive curves (pass 2) are one line where they follow them together, overlapping or
leaving at most ``tuning.shared_gap`` d_eps between them, along at least
``tuning.shared_share`` of the shorter one's length or ``tuning.shared_length`` d_eps,
summed over the curves (a long stroke through crossings follows many short curves, each
cut at a crossing). Groups are the connected components of that relation; pass 4 checks
each by its fit. The pairs are handed on, those sharing most first.

Invariant: without merges (epsilon 0) every piece follows only its own curves, and two
pieces share a curve only where their ink coincides.
"""

from __future__ import annotations

import numpy as np

from ..arrays.components import component_labels
from ..arrays.polylines import total_lengths
from .work import Work

__all__ = ["run", "shared_curve_pairs"]


def shared_curve_pairs(piece: np.ndarray, curve: np.ndarray, at: np.ndarray,
                       lengths: np.ndarray, h: float, need_share: float, need_length: float,
                       gap: float) -> tuple[np.ndarray, np.ndarray]:
    """Pairs of pieces that follow the same curves together (see the module): summed over
    every curve both follow where they overlap (or leave at most ``gap`` between them),
    the shorter of the two lengths along it; a pair counts where that sum is at least
    ``need_share`` of the shorter piece's length or ``need_length``.

    Args:
        piece, curve, at: per sample, its piece, the curve it follows (-1: none) and where
            along that curve.
        lengths: each piece's length.
        h: the samples' spacing (each stands for this much of its piece).
        need_share, need_length: see above (the smaller is enough).
        gap: the widest gap between where the two follow a curve.

    Returns:
        (k, 2) piece indices, the smaller first, and (k,) the length each pair shares.

    >>> piece = np.array([0, 0, 0, 1, 1, 1, 2])
    >>> curve = np.array([5, 5, 5, 5, 5, 5, 5])
    >>> at = np.array([0.0, 1, 2, 1.5, 2.5, 3.5, 9.0])
    >>> pairs, shared = shared_curve_pairs(piece, curve, at, np.array([2.0, 2.0, 0.1]), 1.0,
    ...                                    0.5, 9, 0.5)  # 2 is too far along from both
    >>> pairs.tolist(), shared.tolist()
    ([[0, 1]], [3.0])
    """
    ok = curve >= 0
    piece, curve, at = piece[ok], curve[ok], at[ok]
    if not len(piece):
        return np.zeros((0, 2), dtype=np.intp), np.zeros(0)
    n = int(max(piece.max() + 1, len(lengths)))
    key = curve.astype(np.int64) * n + piece
    order = np.argsort(key, kind="stable")
    key, at = key[order], at[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    lo = np.minimum.reduceat(at, starts)
    hi = np.maximum.reduceat(at, starts)
    along = np.diff(np.r_[starts, len(key)]) * h
    p = piece[order][starts]
    c = curve[order][starts]
    firsts, seconds, shared = [], [], []
    bounds = np.flatnonzero(np.r_[True, c[1:] != c[:-1], True])
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a < 2:
            continue
        overlap = (np.minimum(hi[a:b, None], hi[None, a:b])
                   - np.maximum(lo[a:b, None], lo[None, a:b]))
        x, y = np.nonzero(np.triu(overlap >= -gap, 1))
        firsts.append(p[a:b][x])
        seconds.append(p[a:b][y])
        shared.append(np.minimum(along[a:b][x], along[a:b][y]))
    if not firsts:
        return np.zeros((0, 2), dtype=np.intp), np.zeros(0)
    x, y = np.concatenate(firsts), np.concatenate(seconds)
    x, y = np.minimum(x, y), np.maximum(x, y)
    pair, inverse = np.unique(x.astype(np.int64) * n + y, return_inverse=True)
    total = np.bincount(inverse, weights=np.concatenate(shared))
    x, y = pair // n, pair % n
    enough = total >= np.minimum(need_share * np.minimum(lengths[x], lengths[y]), need_length)
    return np.stack([x[enough], y[enough]], axis=1).astype(np.intp), total[enough]


def run(work: Work) -> Work:
    n = len(work.pieces)
    if work.sample_curve is None or not work.merged:
        return work.with_(labels=np.arange(n))
    t = work.tuning
    sizes = work.piece_sizes()
    piece = np.repeat(np.arange(n), sizes)
    pairs, shared = shared_curve_pairs(piece, work.sample_curve, work.sample_at,
                                       total_lengths(work.pieces), work.h, t.shared_share,
                                       t.shared_length * work.d, t.shared_gap * work.d)
    pairs = pairs[np.argsort(-shared, kind="stable")]  # those sharing most first (pass 4)
    return work.with_(labels=component_labels(n, pairs), pairs=pairs)
