"""Fourier descriptors of closed outlines (paper section 3.2.1), batched with numpy.

An outline is resampled to N points evenly spaced by arc length; its centroid distance
R(t) is transformed with the FFT; the descriptor is |a_1..a_N/2| / |a_0|. Two shapes differ
by the Euclidean distance of their descriptors. Magnitudes make it independent of the start
point and rotation, the centroid of translation, and dividing by |a_0| of scale.

A curve is described as the slender ring p0 .. p_n-1, p_n-2 .. p1 (walked there and back).
"""

from __future__ import annotations

import numpy as np

DEFAULT_SAMPLES = 256


def slender_ring(curve: np.ndarray) -> np.ndarray:
    """The curve walked forth and back: p0..p_{n-1}, p_{n-2}..p1 (closed implicitly)."""
    return np.concatenate([curve, curve[-2:0:-1]])


def resample_rings(rings: list[np.ndarray], n: int) -> np.ndarray:
    """Resample closed rings (first point not repeated) to ``n`` points each by arc length.

    Returns an array (len(rings), n, 2). All rings are handled in one vectorised pass.
    """
    counts = np.fromiter((len(r) + 1 for r in rings), dtype=np.intp, count=len(rings))
    closed = np.concatenate([np.concatenate([r, r[:1]]) for r in rings])
    owner = np.repeat(np.arange(len(rings)), counts)
    seg = np.hypot(*np.diff(closed, axis=0).T)
    seg[owner[1:] != owner[:-1]] = 0.0  # no segment between consecutive rings
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    ends = starts + counts - 1
    length = cum[ends] - cum[starts]
    frac = np.arange(n) / n
    target = cum[starts][:, None] + length[:, None] * frac[None, :]
    # the segment each target falls in, kept inside its own ring
    idx = np.searchsorted(cum, target.ravel(), side="right") - 1
    idx = np.clip(idx, np.repeat(starts, n), np.repeat(ends - 1, n))
    seg_len = cum[idx + 1] - cum[idx]
    t = np.divide(target.ravel() - cum[idx], seg_len, out=np.zeros_like(seg_len),
                  where=seg_len > 0)
    pts = closed[idx] + (closed[idx + 1] - closed[idx]) * t[:, None]
    return pts.reshape(len(rings), n, 2)


def fourier_descriptors(rings: list[np.ndarray], n: int = DEFAULT_SAMPLES) -> np.ndarray:
    """Descriptors (len(rings), n // 2) of closed rings given as (k, 2) point arrays."""
    if not rings:
        return np.empty((0, n // 2))
    samples = resample_rings(rings, n)
    centroid = samples.mean(axis=1, keepdims=True)
    radius = np.hypot(*(samples - centroid).transpose(2, 0, 1))
    coeffs = np.abs(np.fft.rfft(radius, axis=1)) / n  # a_0 .. a_{n/2}
    a0 = coeffs[:, :1]
    return np.divide(coeffs[:, 1:], a0, out=np.zeros_like(coeffs[:, 1:]), where=a0 > 0)


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
    radius = np.hypot(*(samples - samples.mean(axis=0)).T)
    coeffs = np.abs(np.fft.rfft(radius)) / n
    return coeffs[1:] / coeffs[0] if coeffs[0] > 0 else np.zeros(n // 2)


def fd_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distance of descriptors (broadcasts over leading axes)."""
    return np.sqrt(((np.asarray(a) - np.asarray(b)) ** 2).sum(axis=-1))
