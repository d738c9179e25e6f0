"""Piecewise cubic Bezier fitting (Schneider, "An algorithm for automatically fitting
digitized curves", Graphics Gems 1990), with sharp corners kept as corners.

No maintained numpy library fits corner-aware least-squares Beziers to polylines (the
``bezier`` package evaluates curves but does not fit them), so it is written out here.
Curves are (3k + 1, 2) arrays of control points: p0, c1, c2, p1, c1, c2, p2, ...
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..arrays.polylines import arc_lengths, end_to_end, gaussian_kernel, smoothed_ring, split

__all__ = [
    "MAX_DEPTH", "SAMPLES_PER_SEGMENT", "corner_indices", "evaluate_bezier", "fit_bezier",
    "fit_beziers", "sample_bezier", "smooth_between_corners", "subdivide_bezier", "turning_on",
]


def _basis(t: np.ndarray) -> np.ndarray:
    """The cubic Bernstein basis at parameters t: (len(t), 4)."""
    r = 1 - t
    basis = np.empty((len(t), 4))
    basis[:, 0] = r * r * r
    basis[:, 1] = 3 * r * r * t
    basis[:, 2] = 3 * r * t * t
    basis[:, 3] = t * t * t
    return basis


#: steps per cubic of the polyline sampled from each output stroke's Bezier curve: what
#: the output's ``points`` hold, and what the add-on counts on to find the knots in them
SAMPLES_PER_SEGMENT = 12


def evaluate_bezier(ctrl: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Points of one cubic, (4, d) control points, at parameters t (any dimension d).

    >>> evaluate_bezier(np.array([[0., 0], [1, 2], [2, 2], [3, 0]]), [0, 0.5, 1]).tolist()
    [[0.0, 0.0], [1.5, 1.5], [3.0, 0.0]]
    """
    return _basis(np.asarray(t, dtype=float)) @ ctrl


def sample_bezier(curve: np.ndarray, per_segment: int = SAMPLES_PER_SEGMENT) -> np.ndarray:
    """A polyline through a piecewise Bezier curve, (3k + 1, d) control points,
    ``per_segment`` steps per cubic: point ``i * per_segment`` is knot ``i``.

    >>> sample_bezier(np.array([[0., 0], [1, 0], [2, 0], [3, 0]]), 3).tolist()
    [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]
    """
    t = np.linspace(0, 1, per_segment + 1)
    segs = [evaluate_bezier(curve[i:i + 4], t if i == 0 else t[1:])
            for i in range(0, len(curve) - 1, 3)]
    return np.concatenate(segs)


def _blossom(u: float, v: float, w: float) -> np.ndarray:
    """The weights of a cubic's 4 control points in its blossom at (u, v, w)."""
    return np.array([(1 - u) * (1 - v) * (1 - w),
                     u * (1 - v) * (1 - w) + (1 - u) * v * (1 - w) + (1 - u) * (1 - v) * w,
                     u * v * (1 - w) + u * (1 - v) * w + (1 - u) * v * w,
                     u * v * w])


def subdivide_bezier(curve: np.ndarray, parts: int) -> np.ndarray:
    """The same piecewise Bezier curve, (3k + 1, d) control points, with each cubic split
    into ``parts`` cubics at equal parameter steps: exactly the same shape, ``parts`` times
    as many knots (knot ``i`` of the result is point ``i * per_segment / parts`` of
    :func:`sample_bezier`), so that values given per knot can follow a profile along it.

    >>> c = np.array([[0., 0], [1, 2], [2, 2], [3, 0]])
    >>> subdivide_bezier(c, 2)[[0, 3, 6]].tolist()  # the middle knot is the curve at 1/2
    [[0.0, 0.0], [1.5, 1.5], [3.0, 0.0]]
    """
    segments = curve[np.arange(0, len(curve) - 1, 3)[:, None] + np.arange(4)]  # (k, 4, d)
    inner = np.einsum("pc,kcd->kpd", _subdivision_weights(parts),
                      segments).reshape(-1, curve.shape[1])
    return np.vstack([inner, curve[-1:]])


@lru_cache(maxsize=8)
def _subdivision_weights(parts: int) -> np.ndarray:
    """(3 * parts, 4): the weights of a cubic's control points in the first three control
    points of each of its ``parts`` pieces (a few sizes are asked for, each many times)."""
    edges = np.linspace(0.0, 1.0, parts + 1)
    weights = np.concatenate([np.stack([_blossom(a, a, a), _blossom(a, a, b),
                                        _blossom(a, b, b)]) for a, b in zip(edges, edges[1:])])
    weights.flags.writeable = False
    return weights


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.hypot(*v)
    return v / n if n > 0 else v


def corner_indices(points: np.ndarray, corner_angle_deg: float, reach: float,
                   round_share: float | None = None) -> list[int]:
    """Indices where the polyline turns by more than the angle within ``reach`` each side;
    with ``round_share``, not where it goes on turning that way beyond, at least that
    share as fast (:func:`turning_on`: a small round shape, not a corner).

    >>> t = np.linspace(0, 2 * np.pi, 40)
    >>> ring = np.stack([np.cos(t), np.sin(t)], axis=1)  # turns 86 degrees within 1.5 each side
    >>> len(corner_indices(ring, 60, 1.5)) > 0, corner_indices(ring, 60, 1.5, 0.5)
    (True, [])
    """
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
    if round_share is not None:
        corners = [k for k in corners if not turning_on(points, s, k, reach, round_share)]
    return corners


def turning_on(points: np.ndarray, s: np.ndarray, k: int, reach: float, share: float
               ) -> bool:
    """Whether the polyline (arc lengths ``s``), turning at ``k`` within ``reach`` each
    side, goes on turning the same way over the next ``reach`` beyond (on each side that
    has ink there), at least ``share`` as fast per length: a small round shape (an eye, a
    dot, a curl), not a corner, whose arms run on straight, or bend much less. A polyline
    with ink beyond on neither side (shorter than four reaches about ``k``) is asked again
    at the reach it holds on both sides, half the shorter: an eye drawn in one stroke
    turns on all round at its own size, however large the reach.

    >>> t = np.linspace(0, 2 * np.pi, 64)
    >>> ring = np.stack([np.cos(t), np.sin(t)], axis=1)  # round: turning on at every point
    >>> turning_on(ring, arc_lengths(ring), 32, 0.8, 0.5)
    True
    >>> corner = np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 0.5], [1.0, 1.0]])
    >>> turning_on(corner, arc_lengths(corner), 2, 0.5, 0.5)
    False
    >>> eye = ring[:56] * 0.1  # most of a small ring, far shorter than the reach
    >>> turning_on(eye, arc_lengths(eye), 28, 0.8, 0.5)
    True
    """
    at = np.searchsorted(s, s[k] + np.array([-2, -1, 1, 2]) * reach).clip(0, len(points) - 1)
    b2, b1, a1, a2 = at

    def rate(x: int, y: int, z: int) -> float | None:
        """How fast the chord x-y turns into the chord y-z, per length between their
        middles (None where either has no length: the stroke ends within reach)."""
        u, v = points[y] - points[x], points[z] - points[y]
        if not (s[y] > s[x] and s[z] > s[y]):
            return None
        turn = float(np.arctan2(u[0] * v[1] - u[1] * v[0], u @ v))
        return turn / ((s[z] - s[x]) / 2)

    here = rate(b1, k, a1)
    beyond = [r for r in (rate(b2, b1, k), rate(k, a1, a2)) if r is not None]
    if not beyond and reach > 0:  # a short stroke: asked again at its own size
        fits = min(s[k] - s[0], s[-1] - s[k]) / 2
        if 0 < fits < reach:
            return turning_on(points, s, k, fits, share)
    return bool(here and beyond and all(r / here >= share for r in beyond))


#: a piece of n samples is smoothed by a sigma of at most n / SIGMA_SHARE samples: as much
#: as a quarter turn of a circle n samples round allows (sigma at most half its radius,
#: which shrinks it by at most 12%), so that no amount of smoothing flattens a short
#: piece into its chord or a small ring into a lemon: smoothing is monotone, and stops
#: where the line's own size says
SIGMA_SHARE = 4 * np.pi


def smooth_between_corners(points: np.ndarray, sigma: float, corners: list[int],
                           closed: bool = False) -> np.ndarray:
    """An evenly spaced polyline smoothed by a Gaussian of ``sigma`` samples, piece by piece
    between its ``corners`` (indices), which stay where they are, as do the ends of an open
    polyline: each piece is mirrored through its ends (2 p0 - p), so that a straight end
    stays straight and does not shrink. A closed polyline without corners wraps round.
    Each piece's sigma is at most its samples over :data:`SIGMA_SHARE`: more smoothing
    never makes a line less smooth, nor a short piece a chord.

    >>> line = np.column_stack([np.arange(60.0), np.r_[[0, 0, 1], np.zeros(57)]])
    >>> smooth_between_corners(line, 1.0, []).round(2)[[0, 2, 59]].tolist()
    [[0.0, 0.0], [2.0, 0.4], [59.0, 0.0]]
    >>> t = np.linspace(0, 2 * np.pi, 41)  # a ring 40 samples round: sigma at most 3.2
    >>> ring = np.column_stack([np.cos(t), np.sin(t)])
    >>> [round(float(np.hypot(*smooth_between_corners(ring, s, [], True)[0])), 3)
    ...  for s in (1.0, 3.0, 30.0)]
    [0.988, 0.896, 0.884]
    """
    if sigma <= 0 or len(points) < 3:
        return points
    if closed and not corners:
        ring_sigma = min(sigma, (len(points) - 1) / SIGMA_SHARE)
        return smoothed_ring(points, ring_sigma) if ring_sigma > 0 else points
    out = points.copy()
    bounds = [0, *sorted(set(corners)), len(points) - 1]
    for a, b in zip(bounds[:-1], bounds[1:]):
        piece = points[a:b + 1]
        piece_sigma = min(sigma, len(piece) / SIGMA_SHARE)
        half = int(np.ceil(3 * piece_sigma))
        if len(piece) < 3 or half < 1:
            continue
        h = min(half, len(piece) - 1)
        head = 2 * piece[0] - piece[h:0:-1]
        tail = 2 * piece[-1] - piece[-2:-2 - h:-1]
        pad = np.concatenate([head, piece, tail])
        k = gaussian_kernel(piece_sigma, h)
        smooth = np.column_stack([np.convolve(pad[:, d], k, mode="valid") for d in (0, 1)])
        out[a + 1:b] = smooth[1:-1]
    return out


#: a piece is split at most this deep (2 ** 25 cubics: never reached in practice)
MAX_DEPTH = 24


def _segment_sum(values: np.ndarray, first: np.ndarray) -> np.ndarray:
    """The sum over each piece (contiguous runs starting at ``first``): the same for a
    piece whatever pieces are summed beside it."""
    return np.add.reduceat(values, first)


def _fit_cubics(pts: np.ndarray, basis: np.ndarray, which: np.ndarray, first: np.ndarray,
                last: np.ndarray, t0: np.ndarray, t1: np.ndarray, arc: np.ndarray
                ) -> np.ndarray:
    """Least-squares cubics (m, 4, 2) with fixed ends and fixed end tangent directions,
    one per piece, the points taken at parameters whose Bernstein ``basis`` is given;
    ``arc`` is each piece's path length."""
    p0, p3 = pts[first], pts[last]
    b1, b2 = basis[:, 1], basis[:, 2]
    rest = pts - (basis[:, 0] + b1)[:, None] * p0[which] - (b2 + basis[:, 3])[:, None] * p3[which]
    t0w, t1w = t0[which], t1[which]
    c00 = _segment_sum(b1 * b1, first) * (t0 * t0).sum(axis=1)
    c01 = _segment_sum(b1 * b2, first) * (t0 * t1).sum(axis=1)
    c11 = _segment_sum(b2 * b2, first) * (t1 * t1).sum(axis=1)
    x0 = _segment_sum(b1 * (rest * t0w).sum(axis=1), first)
    x1 = _segment_sum(b2 * (rest * t1w).sum(axis=1), first)
    det = c00 * c11 - c01 * c01
    chord = np.hypot(p3[:, 0] - p0[:, 0], p3[:, 1] - p0[:, 1])
    solved = np.abs(det) > 1e-12 * np.maximum(c00 * c11, 1e-300)
    safe = np.where(solved, det, 1.0)
    alpha1 = np.where(solved, (x0 * c11 - x1 * c01) / safe, 0.0)
    alpha2 = np.where(solved, (c00 * x1 - c01 * x0) / safe, 0.0)
    # Wu/Barsky: a degenerate solve, or handles longer than the whole piece (which would
    # loop far away between the samples): fall back to a third of the chord
    bad = (np.minimum(alpha1, alpha2) < 1e-6 * chord) | (np.maximum(alpha1, alpha2) > arc)
    alpha1 = np.where(bad, chord / 3, alpha1)
    alpha2 = np.where(bad, chord / 3, alpha2)
    return np.stack([p0, p0 + alpha1[:, None] * t0, p3 + alpha2[:, None] * t1, p3], axis=1)


def _on_curves(ctrl: np.ndarray, basis: np.ndarray, which: np.ndarray) -> np.ndarray:
    """Each point's cubic (``ctrl[which]``) at its parameter, given their ``basis``."""
    c = ctrl[which]
    return (basis[:, :1] * c[:, 0] + basis[:, 1:2] * c[:, 1] + basis[:, 2:3] * c[:, 2]
            + basis[:, 3:] * c[:, 3])


def _reparameterise(ctrl: np.ndarray, diff: np.ndarray, u: np.ndarray, which: np.ndarray
                    ) -> np.ndarray:
    """One Newton-Raphson step towards the nearest curve parameter of each point, given
    ``diff``, its cubic (``ctrl[which]``) at ``u`` minus the point."""
    d1 = 3 * (ctrl[:, 1:] - ctrl[:, :-1])
    d2 = 2 * (d1[:, 1:] - d1[:, :-1])
    d1, d2 = d1[which], d2[which]
    r = (1 - u)[:, None]
    uu = u[:, None]
    q1 = r * r * d1[:, 0] + 2 * r * uu * d1[:, 1] + uu * uu * d1[:, 2]
    q2 = r * d2[:, 0] + uu * d2[:, 1]
    num = (diff * q1).sum(axis=1)
    den = (q1 * q1).sum(axis=1) + (diff * q2).sum(axis=1)
    step = np.divide(num, den, out=np.zeros_like(num), where=np.abs(den) > 1e-12)
    return np.minimum(np.maximum(u - step, 0.0), 1.0)


def _fit_once(pieces: list[np.ndarray], t0: np.ndarray, t1: np.ndarray, tol: float
              ) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """The least-squares cubic of each piece, then up to four Newton steps on its
    parameters while it misses a point by more than ``tol``; all pieces at once (each
    piece's arithmetic is its own: a piece fits the same in any batch).

    Returns the cubics (m, 4, 2), each one's largest miss and its misses at its points."""
    pts, first, last = end_to_end(pieces)
    sizes = last - first + 1
    which = np.repeat(np.arange(len(pieces)), sizes)
    s = arc_lengths(pts, first, last)
    arc = s[last]
    # by arc length, or evenly where a piece has no length
    u = np.where((arc > 0)[which], s / np.where(arc > 0, arc, 1.0)[which],
                 (np.arange(len(pts)) - first[which]) / (sizes - 1)[which])
    basis = _basis(u)
    ctrl = _fit_cubics(pts, basis, which, first, last, t0, t1, arc)
    trying = np.ones(len(pieces), dtype=bool)
    err = np.zeros(len(pts))
    for attempt in range(5):  # the fit, then up to four Newton steps on its parameters
        diff = _on_curves(ctrl, basis, which) - pts
        moved = trying[which]  # a piece that stopped keeps its cubic and its misses
        err = np.where(moved, np.hypot(diff[:, 0], diff[:, 1]), err)
        worst = np.maximum.reduceat(err, first)
        trying &= worst > tol
        if attempt == 4 or not trying.any():
            break
        u = np.where(trying[which], _reparameterise(ctrl, diff, u, which), u)
        basis = _basis(u)
        ctrl = np.where(trying[:, None, None],
                        _fit_cubics(pts, basis, which, first, last, t0, t1, arc), ctrl)
    return ctrl, worst, split(err, sizes)


def _fit_pieces(pieces: list[tuple[np.ndarray, np.ndarray, np.ndarray]], tol: float
                ) -> list[list[np.ndarray]]:
    """Schneider's fit of each (points, start tangent, end tangent): one cubic if it keeps
    within ``tol``, else the piece split at its worst point, tangent-continuous there, and
    each part fitted again; a level of splitting at a time for all pieces."""
    points = [p for p, _, _ in pieces]
    t0s = [t for _, t, _ in pieces]
    t1s = [t for _, _, t in pieces]
    depth = [0] * len(pieces)
    result: list[np.ndarray | tuple[int, int] | None] = [None] * len(pieces)
    frontier = list(range(len(pieces)))
    while frontier:
        fit = []
        for k in frontier:
            pts = points[k]
            if len(pts) == 2 or (len(pts) <= 3 and np.hypot(*(pts[-1] - pts[0])) == 0):
                d = np.hypot(*(pts[-1] - pts[0])) / 3
                result[k] = np.array([pts[0], pts[0] + d * t0s[k], pts[-1] + d * t1s[k],
                                      pts[-1]])
            else:
                fit.append(k)
        if not fit:
            break
        ctrl, worst, errs = _fit_once([points[k] for k in fit], np.array([t0s[k] for k in fit]),
                                      np.array([t1s[k] for k in fit]), tol)
        frontier = []
        for k, c, w, err in zip(fit, ctrl, worst.tolist(), errs):
            if w <= tol or depth[k] > MAX_DEPTH:
                result[k] = c
                continue
            pts = points[k]
            cut = int(np.clip(np.argmax(err), 1, len(pts) - 2))
            centre = _unit(pts[cut - 1] - pts[cut + 1])
            if not centre.any():
                centre = _unit(pts[cut - 1] - pts[cut])
            left, right = len(points), len(points) + 1
            points += [pts[:cut + 1], pts[cut:]]
            t0s += [t0s[k], -centre]
            t1s += [centre, t1s[k]]
            depth += [depth[k] + 1] * 2
            result += [None, None]
            result[k] = (left, right)
            frontier += [left, right]

    def cubics(k: int) -> list[np.ndarray]:
        r = result[k]
        return [r] if isinstance(r, np.ndarray) else cubics(r[0]) + cubics(r[1])

    return [cubics(k) for k in range(len(pieces))]


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
    return fit_beziers([points], max_error, corner_angle_deg, [closed])[0]


def fit_beziers(polylines: list[np.ndarray], max_error: float, corner_angle_deg: float,
                closed: list[bool], round_share: float | None = None) -> list[np.ndarray]:
    """:func:`fit_bezier` of each polyline, all fitted together (each the same as alone);
    with ``round_share``, a small round shape has no corners (:func:`corner_indices`)."""
    reach = 4 * max_error
    pieces, owner = [], []
    for k, (points, loop) in enumerate(zip(polylines, closed)):
        pts = np.asarray(points, dtype=float)
        keep = np.concatenate([[True], np.hypot(*np.diff(pts, axis=0).T) > 0])
        pts = pts[keep]
        if len(pts) < 2:
            raise ValueError("a curve needs two distinct points")
        cuts = sorted({0, *corner_indices(pts, corner_angle_deg, reach, round_share),
                       len(pts) - 1})
        for i, j in zip(cuts[:-1], cuts[1:]):
            seg = pts[i:j + 1]
            t0 = _end_tangent(seg, reach)
            t1 = _end_tangent(seg[::-1], reach)
            if loop and len(cuts) == 2:  # smooth seam: one tangent through the joint
                seam = _unit(pts[1] - pts[-2])
                if seam.any():
                    t0, t1 = seam, -seam
            pieces.append((seg, t0, t1))
            owner.append(k)
    out: list[list[np.ndarray]] = [[] for _ in polylines]
    for k, cubics in zip(owner, _fit_pieces(pieces, max_error)):
        out[k] += cubics
    return [np.concatenate([c[0]] + [p[1:] for p in c[1:]]) for c in out]
