"""Fourier descriptors of closed outlines (paper section 3.2.1).

An outline is resampled to N points evenly spaced by arc length; its centroid distance
R(t) is transformed with the FFT; the descriptor is |a_1..a_N/2| / |a_0|. Two shapes differ
by the Euclidean distance of their descriptors. Magnitudes make it independent of the start
point and rotation, the centroid of translation, and dividing by |a_0| of scale.

Rings are resampled one at a time with np.interp: for the few hundred points of a ring
that beats batched fancy indexing, and the merge loop asks for one or two at a time.

A curve is described as the slender ring p0 .. p_n-1, p_n-2 .. p1 (walked there and back).
"""

from __future__ import annotations

import numpy as np

DEFAULT_SAMPLES = 256


def slender_ring(curve: np.ndarray) -> np.ndarray:
    """The curve walked forth and back: p0..p_{n-1}, p_{n-2}..p1 (closed implicitly)."""
    return np.concatenate([curve, curve[-2:0:-1]])


def resample_ring(ring: np.ndarray, n: int) -> np.ndarray:
    """A closed ring (first point not repeated) resampled to ``n`` points evenly spaced by
    arc length, starting at its first point."""
    closed = np.concatenate([ring, ring[:1]])
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    t = np.arange(n) * (s[-1] / n)
    return np.stack([np.interp(t, s, closed[:, 0]), np.interp(t, s, closed[:, 1])], axis=1)


def fourier_descriptors(rings: list[np.ndarray], n: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Descriptors (len(rings), n // 2) of closed rings given as (k, 2) point arrays."""
    out = np.empty((len(rings), n // 2))
    for k, ring in enumerate(rings):
        out[k] = _descriptor_of_samples(resample_ring(ring, n), n)
    return out


def fourier_descriptor(ring: np.ndarray, n: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Descriptor of one closed ring (first point not repeated)."""
    return fourier_descriptors([np.asarray(ring, dtype=float)], n)[0]


def curve_descriptors(curves: list[np.ndarray], n: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Descriptors of open curves, each taken as its slender ring.

    The slender ring is resampled directly: arc position t along the ring of length 2L is
    the curve's point at t for t < L and at 2L - t after, so it is never built.
    """
    out = np.empty((len(curves), n // 2))
    for k, curve in enumerate(curves):
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(curve, axis=0).T))])
        t = np.arange(n) * (2.0 * s[-1] / n)
        u = np.where(t <= s[-1], t, 2.0 * s[-1] - t)
        samples = np.stack([np.interp(u, s, curve[:, 0]), np.interp(u, s, curve[:, 1])], axis=1)
        out[k] = _descriptor_of_samples(samples, n)
    return out


def _descriptor_of_samples(samples: np.ndarray, n: int) -> np.ndarray:
    centre = samples.sum(axis=0) / n
    radius = np.sqrt(((samples - centre) ** 2).sum(axis=1))
    coeffs = np.abs(np.fft.rfft(radius))
    return coeffs[1:] / coeffs[0] if coeffs[0] > 0 else np.zeros(n // 2)


def fd_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distance of descriptors (broadcasts over leading axes)."""
    return np.sqrt(((np.asarray(a) - np.asarray(b)) ** 2).sum(axis=-1))
