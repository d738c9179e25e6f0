"""Curve-curve merging: when two curves depict one stroke, and the curve that replaces them.

Two curves are neighbours (paper 3.2.2, with d_eps = alpha * D and d_theta = ``angle``)
when they run side by side or continue each other:

* side by side: most of the shorter curve lies within d_eps of the longer one and their
  tangents there differ by less than d_theta (checked along the whole overlap, not at the
  single closest pair of points, which a narrow V shape would pass);
* end to end: an end of one lies within d_eps of an end of the other and the second
  carries on in the direction the first was heading.

The merged curve follows the weighted middle of the two where they overlap and each one
alone where it does not, blending over d_eps so that no kink appears where one ends.
Curves are handled as :class:`SampledCurve` (evenly resampled once, then reused).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from .geometry import arc_lengths, resample_polyline, unit_tangents

#: fraction of the shorter curve that must lie beside the longer one
MIN_OVERLAP = 0.5


def sample_spacing(d_eps: float) -> float:
    """Spacing at which curves are resampled for pairing and merging: fine enough to
    follow a bundle d_eps wide, coarse enough to stay cheap."""
    return d_eps / 2


@dataclass(eq=False)
class SampledCurve:
    """A polyline resampled evenly, with what pairing and merging need of it."""

    points: np.ndarray
    s: np.ndarray  # arc length at each point
    tangents: np.ndarray
    line: shapely.LineString

    @classmethod
    def of(cls, points: np.ndarray, spacing: float) -> SampledCurve:
        pts = resample_polyline(points, spacing)
        return cls(pts, arc_lengths(pts), unit_tangents(pts), shapely.LineString(pts))

    @property
    def length(self) -> float:
        return float(self.s[-1])


def _project(base: SampledCurve, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Arc-length parameter of ``pts`` along ``base``, extended linearly past its ends,
    and their distance to it."""
    geoms = shapely.points(pts)
    s = shapely.line_locate_point(base.line, geoms)
    dist = shapely.distance(geoms, base.line)
    b = base.points
    t0 = base.tangents[0]
    t1 = base.tangents[-1]
    before = (pts - b[0]) @ t0
    after = (pts - b[-1]) @ t1
    s = np.where((s <= 1e-12) & (before < 0), before, s)
    s = np.where((s >= base.length - 1e-12) & (after > 0), base.length + after, s)
    return s, dist


def _continues(a: SampledCurve, b: SampledCurve, d_eps: float, cos_max: float) -> bool:
    """An end of ``a`` near an end of ``b``, ``b`` heading on the way ``a`` was going."""
    for ea, da in ((a.points[0], -a.tangents[0]), (a.points[-1], a.tangents[-1])):
        for eb, db in ((b.points[0], b.tangents[0]), (b.points[-1], -b.tangents[-1])):
            if np.hypot(*(ea - eb)) <= d_eps and da @ db >= cos_max:
                return True
    return False


def _straight_and_askew(a: SampledCurve, b: SampledCurve, cos_max: float) -> bool:
    """Both nearly straight and at an angle: they can neither run side by side nor
    continue each other (the common case of lines crossing at a node, decided cheaply)."""
    ca, cb = a.points[-1] - a.points[0], b.points[-1] - b.points[0]
    la, lb = np.hypot(*ca), np.hypot(*cb)
    if la < 0.95 * a.length or lb < 0.95 * b.length or la == 0 or lb == 0:
        return False
    return abs(ca @ cb) / (la * lb) < cos_max


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3 - 2 * x)


def _blend(long_: SampledCurve, wl: float, short: SampledCurve, ws: float, s_s: np.ndarray,
           d_eps: float, spacing: float) -> np.ndarray:
    pts_s = short.points
    if s_s[-1] < s_s[0]:
        pts_s, s_s = pts_s[::-1], s_s[::-1]
    s_s = np.maximum.accumulate(s_s)
    s_l = long_.s
    lo, hi = min(0.0, s_s[0]), max(s_l[-1], s_s[-1])
    t = np.linspace(lo, hi, max(2, int(np.ceil((hi - lo) / spacing)) + 1))
    in_l = (t >= 0) & (t <= s_l[-1])
    in_s = (t >= s_s[0]) & (t <= s_s[-1])
    w_l = wl * in_l * (1e-3 + _smoothstep(np.minimum(t, s_l[-1] - t) / d_eps))
    w_s = ws * in_s * (1e-3 + _smoothstep(np.minimum(t - s_s[0], s_s[-1] - t) / d_eps))
    pl = np.stack([np.interp(t, s_l, long_.points[:, 0]),
                   np.interp(t, s_l, long_.points[:, 1])], axis=1)
    if s_s[-1] > s_s[0]:
        ps = np.stack([np.interp(t, s_s, pts_s[:, 0]), np.interp(t, s_s, pts_s[:, 1])], axis=1)
    else:
        ps = np.repeat(pts_s[:1], len(t), axis=0)
    total = w_l + w_s
    keep = total > 0
    merged = (w_l[:, None] * pl + w_s[:, None] * ps)[keep] / total[keep][:, None]
    step = np.hypot(*np.diff(merged, axis=0).T)
    return merged[np.concatenate([[True], step > 1e-12])]


def pair_and_merge(a: SampledCurve, wa: float, b: SampledCurve, wb: float, d_eps: float,
                   max_angle_deg: float, sides_only: bool = False
                   ) -> tuple[str | None, np.ndarray | None]:
    """How two curves pair ('side', 'end' or None) and, if they do, their merged polyline.

    The merged polyline keeps within d_eps of both curves, or the pair is refused.
    """
    long_, wl, short, ws = (a, wa, b, wb) if a.length >= b.length else (b, wb, a, wa)
    cos_max = np.cos(np.radians(max_angle_deg))
    how = None
    if _straight_and_askew(a, b, cos_max):
        return None, None
    # a few points first: most candidate pairs only touch at a node and are refused here
    probe = short.points[np.linspace(0, len(short.points) - 1, 9).astype(int)]
    if (shapely.distance(shapely.points(probe), long_.line) <= d_eps).mean() >= MIN_OVERLAP - 0.2:
        s, dist = _project(long_, short.points)
        near = dist <= d_eps
        if near.mean() >= MIN_OVERLAP:
            idx = np.clip(np.searchsorted(long_.s, s[near]), 0, len(long_.s) - 1)
            cos = np.abs((short.tangents[near] * long_.tangents[idx]).sum(axis=1))
            if np.median(cos) >= cos_max:
                how = "side"
    if how is None and not sides_only and _continues(a, b, d_eps, cos_max):
        how = "end"
        s, _ = _project(long_, short.points)
    if how is None:
        return None, None
    spacing = float(long_.s[1] - long_.s[0]) if len(long_.s) > 1 else sample_spacing(d_eps)
    merged = _blend(long_, wl, short, ws, s, d_eps, spacing)
    if len(merged) < 2:
        return None, None
    line = shapely.LineString(merged)
    for parent in (a, b):
        if shapely.distance(shapely.points(parent.points), line).max() > d_eps:
            return None, None
    return how, merged
