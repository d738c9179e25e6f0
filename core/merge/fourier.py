"""Fourier descriptors of closed outlines (paper section 3.2.1).

An outline is resampled to N points evenly spaced by arc length; its centroid distance
R(t) is transformed with the FFT; the descriptor is |a_1..a_N/2| / |a_0|. Two shapes differ
by the Euclidean distance of their descriptors. Magnitudes make it independent of the start
point and rotation, the centroid of translation, and dividing by |a_0| of scale.

Many rings are resampled at once, laid end to end (:mod:`core.arrays.polylines`), and transformed
with one FFT: the merge loop costs many pairs in a batch.

A curve is described as the slender ring p0 .. p_n-1, p_n-2 .. p1 (walked there and back).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..arrays.polylines import Polylines, arc_lengths, end_to_end, points_at

__all__ = [
    "DEFAULT_SAMPLES", "curve_descriptors", "fd_distance", "fourier_descriptor",
    "fourier_descriptors", "resample_ring", "resample_rings", "slender_ring",
]

DEFAULT_SAMPLES = 256


def slender_ring(curve: np.ndarray) -> np.ndarray:
    """The curve walked forth and back: p0..p_{n-1}, p_{n-2}..p1 (closed implicitly)."""
    return np.concatenate([curve, curve[-2:0:-1]])


def resample_ring(ring: np.ndarray, n: int) -> np.ndarray:
    """A closed ring (first point not repeated) resampled to ``n`` points evenly spaced by
    arc length, starting at its first point."""
    return resample_rings([ring], n)[0]


def resample_rings(rings: list[np.ndarray], n: int) -> np.ndarray:
    """Rings resampled as by :func:`resample_ring`, all at once: (len(rings), n, 2)."""
    closed = [np.concatenate([r, r[:1]]) for r in rings]
    return _sample_end_to_end(closed, n, lambda t, length: t * length)


def _sample_end_to_end(lines: list[np.ndarray], n: int, where) -> np.ndarray:
    """Samples of many polylines at arc positions ``where(k / n, length)``, k < n, laid
    end to end (:mod:`core.arrays.polylines`: the same to the bit as for each line alone)."""
    if len(lines) == 1:  # the merge loop's usual case: np.interp on the line itself
        s = arc_lengths(lines[0])
        return points_at(where(_fractions(n), s[-1]), s, lines[0])[None]
    points, first, last = end_to_end(lines)
    s = arc_lengths(points, first, last)
    t = where(_fractions(n), s[last][:, None]).ravel()
    which = np.repeat(np.arange(len(lines)), n)
    return Polylines.of_flat(s, points, first, last).at(which, t).reshape(len(lines), n, 2)


@lru_cache(maxsize=8)
def _fractions(n: int) -> np.ndarray:
    """k / n for k < n (shared, read only)."""
    fractions = np.arange(n) / n
    fractions.flags.writeable = False
    return fractions


@lru_cache(maxsize=8)
def _ones(n: int) -> np.ndarray:
    ones = np.ones(n)
    ones.flags.writeable = False
    return ones


def fourier_descriptors(rings: list[np.ndarray], n: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Descriptors (len(rings), n // 2) of closed rings given as (k, 2) point arrays."""
    if not rings:
        return np.empty((0, n // 2))
    return _descriptors_of_samples(resample_rings(rings, n), n)


def fourier_descriptor(ring: np.ndarray, n: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Descriptor of one closed ring (first point not repeated)."""
    return fourier_descriptors([np.asarray(ring, dtype=float)], n)[0]


def curve_descriptors(curves: list[np.ndarray], n: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Descriptors of open curves, each taken as its slender ring.

    The slender ring is resampled directly: arc position t along the ring of length 2L is
    the curve's point at t for t < L and at 2L - t after, so it is never built.
    """
    if not curves:
        return np.empty((0, n // 2))
    samples = _sample_end_to_end(list(curves), n,
                                 lambda t, length: length - np.abs(length - 2.0 * t * length))
    return _descriptors_of_samples(samples, n)


def _descriptors_of_samples(samples: np.ndarray, n: int) -> np.ndarray:
    """Descriptors of (m, n, 2) evenly spaced samples; a shape with no extent gets zeros."""
    centre = (_ones(n) @ samples) / n  # the samples' mean: matmul is the quicker sum
    radius = np.hypot(samples[:, :, 0] - centre[:, :1], samples[:, :, 1] - centre[:, 1:])
    coeffs = np.abs(np.fft.rfft(radius, axis=1))
    a0 = coeffs[:, :1]
    if a0.all():
        return coeffs[:, 1:] / a0
    return np.divide(coeffs[:, 1:], a0, out=np.zeros((len(samples), n // 2)), where=a0 > 0)


def fd_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distance of descriptors (broadcasts over leading axes)."""
    return np.sqrt(((np.asarray(a) - np.asarray(b)) ** 2).sum(axis=-1))
