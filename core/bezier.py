"""Piecewise cubic Bezier fitting (Schneider, "An algorithm for automatically fitting
digitized curves", Graphics Gems 1990), with sharp corners kept as corners.

No maintained numpy library fits corner-aware least-squares Beziers to polylines (the
``bezier`` package evaluates curves but does not fit them), so it is written out here.
Curves are (3k + 1, 2) arrays of control points: p0, c1, c2, p1, c1, c2, p2, ...
"""

from __future__ import annotations

import math

import numpy as np

from .geometry import arc_lengths


def _basis(t: np.ndarray) -> np.ndarray:
    """The cubic Bernstein basis at parameters t: (len(t), 4)."""
    r = 1 - t
    basis = np.empty((len(t), 4))
    basis[:, 0] = r * r * r
    basis[:, 1] = 3 * r * r * t
    basis[:, 2] = 3 * r * t * t
    basis[:, 3] = t * t * t
    return basis


def evaluate(ctrl: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Points of one cubic (4, 2) at parameters t."""
    return _basis(np.asarray(t, dtype=float)) @ ctrl


def sample(curve: np.ndarray, per_segment: int = 16) -> np.ndarray:
    """A polyline through a piecewise Bezier curve, ``per_segment`` steps per cubic."""
    t = np.linspace(0, 1, per_segment + 1)
    segs = [evaluate(curve[i:i + 4], t if i == 0 else t[1:]) for i in range(0, len(curve) - 1, 3)]
    return np.concatenate(segs)


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.hypot(*v)
    return v / n if n > 0 else v


def corner_indices(points: np.ndarray, corner_angle_deg: float, reach: float) -> list[int]:
    """Indices where the polyline turns by more than the angle within ``reach`` each side."""
    if len(points) < 3:
        return []
    s = arc_lengths(points)
    i = np.arange(len(points))
    back = np.minimum(np.searchsorted(s, s - reach, side="left"), i - 1).clip(0)
    ahead = np.maximum(np.searchsorted(s, s + reach, side="right") - 1, i + 1)
    ahead = ahead.clip(0, len(points) - 1)
    d_in = points[i] - points[back]
    d_out = points[ahead] - points[i]
    n_in, n_out = np.hypot(*d_in.T), np.hypot(*d_out.T)
    ok = (n_in > 0) & (n_out > 0) & (i > 0) & (i < len(points) - 1)
    cos = np.ones(len(points))
    cos[ok] = (d_in[ok] * d_out[ok]).sum(axis=1) / (n_in[ok] * n_out[ok])
    sharp = cos < np.cos(np.radians(corner_angle_deg))
    corners: list[int] = []
    for k in np.flatnonzero(sharp):  # of sharp points closer than reach keep the sharpest
        if corners and s[k] - s[corners[-1]] < reach:
            if cos[k] < cos[corners[-1]]:
                corners[-1] = int(k)
            continue
        corners.append(int(k))
    return corners


def _fit_cubic(pts: np.ndarray, basis: np.ndarray, t0: np.ndarray, t1: np.ndarray,
               arc: float) -> np.ndarray:
    """Least-squares cubic with fixed ends and fixed end tangent directions, the points
    taken at parameters whose Bernstein ``basis`` is given; ``arc`` is their path length."""
    p0, p3 = pts[0], pts[-1]
    b1, b2 = basis[:, 1], basis[:, 2]
    rest = pts - np.outer(basis[:, 0] + b1, p0) - np.outer(b2 + basis[:, 3], p3)
    c00, c01, c11 = (b1 @ b1) * (t0 @ t0), (b1 @ b2) * (t0 @ t1), (b2 @ b2) * (t1 @ t1)
    x0, x1 = b1 @ (rest @ t0), b2 @ (rest @ t1)
    det = c00 * c11 - c01 * c01
    chord = math.hypot(p3[0] - p0[0], p3[1] - p0[1])
    alpha1 = alpha2 = 0.0
    if abs(det) > 1e-12 * max(c00 * c11, 1e-300):
        alpha1, alpha2 = (x0 * c11 - x1 * c01) / det, (c00 * x1 - c01 * x0) / det
    if min(alpha1, alpha2) < 1e-6 * chord or max(alpha1, alpha2) > arc:
        # Wu/Barsky: a degenerate solve, or handles longer than the whole piece (which
        # would loop far away between the samples): fall back to a third of the chord
        alpha1 = alpha2 = chord / 3
    return np.array([p0, p0 + alpha1 * t0, p3 + alpha2 * t1, p3])


def _reparameterise(ctrl: np.ndarray, diff: np.ndarray, u: np.ndarray) -> np.ndarray:
    """One Newton-Raphson step towards the nearest curve parameter of each point, given
    ``diff``, the curve at ``u`` minus the points."""
    d1 = 3 * (ctrl[1:] - ctrl[:-1])
    d2 = 2 * (d1[1:] - d1[:-1])
    r = 1 - u
    q1 = np.outer(r * r, d1[0]) + np.outer(2 * r * u, d1[1]) + np.outer(u * u, d1[2])
    q2 = np.outer(r, d2[0]) + np.outer(u, d2[1])
    num = (diff * q1).sum(axis=1)
    den = (q1 * q1).sum(axis=1) + (diff * q2).sum(axis=1)
    step = np.divide(num, den, out=np.zeros_like(num), where=np.abs(den) > 1e-12)
    return np.minimum(np.maximum(u - step, 0.0), 1.0)


def _fit_piece(pts: np.ndarray, t0: np.ndarray, t1: np.ndarray, tol: float,
               depth: int = 0) -> list[np.ndarray]:
    if len(pts) == 2 or np.hypot(*(pts[-1] - pts[0])) == 0 and len(pts) <= 3:
        d = np.hypot(*(pts[-1] - pts[0])) / 3
        return [np.array([pts[0], pts[0] + d * t0, pts[-1] + d * t1, pts[-1]])]
    s = arc_lengths(pts)
    u = s / s[-1] if s[-1] > 0 else np.linspace(0, 1, len(pts))
    basis = _basis(u)
    ctrl = _fit_cubic(pts, basis, t0, t1, float(s[-1]))
    for attempt in range(5):  # the fit, then up to four Newton steps on its parameters
        diff = basis @ ctrl - pts
        err = np.hypot(diff[:, 0], diff[:, 1])
        if err.max() <= tol or attempt == 4:
            break
        u = _reparameterise(ctrl, diff, u)
        basis = _basis(u)
        ctrl = _fit_cubic(pts, basis, t0, t1, float(s[-1]))
    if err.max() <= tol or depth > 24:
        return [ctrl]
    split = int(np.clip(np.argmax(err), 1, len(pts) - 2))
    centre = _unit(pts[split - 1] - pts[split + 1])
    if not centre.any():
        centre = _unit(pts[split - 1] - pts[split])
    left = _fit_piece(pts[:split + 1], t0, centre, tol, depth + 1)
    right = _fit_piece(pts[split:], -centre, t1, tol, depth + 1)
    return left + right


def _end_tangent(pts: np.ndarray, reach: float) -> np.ndarray:
    s = arc_lengths(pts)
    k = int(np.clip(np.searchsorted(s, reach), 1, len(pts) - 1))
    t = _unit(pts[k] - pts[0])
    return t if t.any() else _unit(pts[-1] - pts[0])


def fit_bezier(points: np.ndarray, max_error: float, corner_angle_deg: float = 50.0,
               closed: bool = False) -> np.ndarray:
    """Piecewise cubic Bezier control points within ``max_error`` of ``points``.

    The polyline is split at corners sharper than ``corner_angle_deg`` (seen over a reach
    of 4 * max_error); each piece is fitted with tangent continuity inside it.
    """
    pts = np.asarray(points, dtype=float)
    keep = np.concatenate([[True], np.hypot(*np.diff(pts, axis=0).T) > 0])
    pts = pts[keep]
    if len(pts) < 2:
        raise ValueError("a curve needs two distinct points")
    reach = 4 * max_error
    cuts = [0, *corner_indices(pts, corner_angle_deg, reach), len(pts) - 1]
    cuts = sorted(set(cuts))
    pieces: list[np.ndarray] = []
    for i, j in zip(cuts[:-1], cuts[1:]):
        seg = pts[i:j + 1]
        t0 = _end_tangent(seg, reach)
        t1 = _end_tangent(seg[::-1], reach)
        if closed and len(cuts) == 2:  # smooth seam: one tangent through the joint
            seam = _unit(pts[1] - pts[-2])
            if seam.any():
                t0, t1 = seam, -seam
        pieces += _fit_piece(seg, t0, t1, max_error)
    out = [pieces[0]] + [p[1:] for p in pieces[1:]]
    return np.concatenate(out)
