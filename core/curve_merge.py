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

import math
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
import shapely

from .geometry import arc_lengths, points_at, resample_polyline, unit_tangents

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
        return cls.of_samples(resample_polyline(points, spacing))

    @classmethod
    def of_samples(cls, pts: np.ndarray) -> SampledCurve:
        """From a polyline already resampled evenly."""
        return cls(pts, arc_lengths(pts), unit_tangents(pts), shapely.linestrings(pts))

    @property
    def length(self) -> float:
        return float(self.s[-1])

    @cached_property
    def point_geoms(self) -> np.ndarray:
        """The points as shapely Points, made once: a curve is measured against many."""
        return shapely.points(self.points)


def _project(base: SampledCurve, curve: SampledCurve) -> tuple[np.ndarray, np.ndarray]:
    """Arc-length parameter of the points of ``curve`` along ``base``, extended linearly
    past its ends, and their distance to it."""
    pts, geoms = curve.points, curve.point_geoms
    s = shapely.line_locate_point(base.line, geoms)
    # the closest point is where the line is at s: cheaper than GEOS measuring again
    off = pts - points_at(s, base.s, base.points)
    dist = np.hypot(off[:, 0], off[:, 1])
    b = base.points
    before = (pts - b[0]) @ base.tangents[0]
    after = (pts - b[-1]) @ base.tangents[-1]
    s = np.where((s <= 1e-12) & (before < 0), before, s)
    s = np.where((s >= base.length - 1e-12) & (after > 0), base.length + after, s)
    return s, dist


def _continues(a: SampledCurve, b: SampledCurve, d_eps: float, cos_max: float) -> bool:
    """An end of ``a`` near an end of ``b``, ``b`` heading on the way ``a`` was going."""
    for ea, da in ((a.points[0], -a.tangents[0]), (a.points[-1], a.tangents[-1])):
        for eb, db in ((b.points[0], b.tangents[0]), (b.points[-1], -b.tangents[-1])):
            if math.hypot(ea[0] - eb[0], ea[1] - eb[1]) <= d_eps and da @ db >= cos_max:
                return True
    return False


def _straight_and_askew(a: SampledCurve, b: SampledCurve, cos_max: float) -> bool:
    """Both nearly straight and at an angle: they can neither run side by side nor
    continue each other (the common case of lines crossing at a node, decided cheaply)."""
    ca, cb = a.points[-1] - a.points[0], b.points[-1] - b.points[0]
    la, lb = math.hypot(ca[0], ca[1]), math.hypot(cb[0], cb[1])
    if la < 0.95 * a.length or lb < 0.95 * b.length or la == 0 or lb == 0:
        return False
    return abs(ca @ cb) / (la * lb) < cos_max


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.minimum(np.maximum(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


def _blend(long_: SampledCurve, wl: float, short: SampledCurve, ws: float, s_s: np.ndarray,
           d_eps: float, spacing: float) -> np.ndarray:
    pts_s = short.points
    if s_s[-1] < s_s[0]:
        pts_s, s_s = pts_s[::-1], s_s[::-1]
    s_s = np.maximum.accumulate(s_s)
    s_l = long_.s
    end_l, start_s, end_s = float(s_l[-1]), float(s_s[0]), float(s_s[-1])
    lo, hi = min(0.0, start_s), max(end_l, end_s)
    n = max(2, math.ceil((hi - lo) / spacing) + 1)
    t = np.arange(n) * ((hi - lo) / (n - 1)) + lo  # np.linspace(lo, hi, n), made directly
    t[-1] = hi
    in_l = (t >= 0) & (t <= end_l)
    in_s = (t >= start_s) & (t <= end_s)
    w_l = wl * in_l * (1e-3 + _smoothstep(np.minimum(t, end_l - t) / d_eps))
    w_s = ws * in_s * (1e-3 + _smoothstep(np.minimum(t - start_s, end_s - t) / d_eps))
    pl = points_at(t, s_l, long_.points)
    ps = points_at(t, s_s, pts_s) if end_s > start_s else np.repeat(pts_s[:1], n, axis=0)
    total = w_l + w_s
    keep = total > 0
    merged = (w_l[:, None] * pl + w_s[:, None] * ps)[keep] / total[keep][:, None]
    d = merged[1:] - merged[:-1]
    moves = np.empty(len(merged), dtype=bool)
    moves[0] = True
    np.greater(np.hypot(d[:, 0], d[:, 1]), 1e-12, out=moves[1:])
    return merged[moves]


def _median(x: np.ndarray) -> float:
    """np.median of a 1-d array, without its generic machinery."""
    x = np.sort(x)
    m = len(x) // 2
    return float(x[m]) if len(x) % 2 else float((x[m - 1] + x[m]) / 2)


@lru_cache(maxsize=4096)
def _probe_index(n: int) -> np.ndarray:
    """Nine indices spread evenly over n points, ends included."""
    return np.linspace(0, n - 1, 9).astype(int)


def pair_and_merge(a: SampledCurve, wa: float, b: SampledCurve, wb: float, d_eps: float,
                   max_angle_deg: float, sides_only: bool = False
                   ) -> tuple[str | None, np.ndarray | None]:
    """How two curves pair ('side', 'end' or None) and, if they do, their merged polyline.

    The merged polyline keeps within d_eps of both curves, or the pair is refused.
    """
    long_, wl, short, ws = (a, wa, b, wb) if a.length >= b.length else (b, wb, a, wa)
    cos_max = math.cos(math.radians(max_angle_deg))
    how = None
    if _straight_and_askew(a, b, cos_max):
        return None, None
    # a few points first: most candidate pairs only touch at a node and are refused here
    probe = short.point_geoms[_probe_index(len(short.points))]
    if np.count_nonzero(shapely.distance(probe, long_.line) <= d_eps) / 9 >= MIN_OVERLAP - 0.2:
        s, dist = _project(long_, short)
        near = dist <= d_eps
        if np.count_nonzero(near) / len(near) >= MIN_OVERLAP:
            idx = np.minimum(np.searchsorted(long_.s, s[near]), len(long_.s) - 1)
            cos = np.abs((short.tangents[near] * long_.tangents[idx]).sum(axis=1))
            if _median(cos) >= cos_max:
                how = "side"
    if how is None and not sides_only and _continues(a, b, d_eps, cos_max):
        how = "end"
        s, _ = _project(long_, short)
    if how is None:
        return None, None
    spacing = float(long_.s[1] - long_.s[0]) if len(long_.s) > 1 else sample_spacing(d_eps)
    merged = _blend(long_, wl, short, ws, s, d_eps, spacing)
    if len(merged) < 2:
        return None, None
    line = shapely.linestrings(merged)
    for parent in (a, b):
        if shapely.distance(parent.point_geoms, line).max() > d_eps:
            return None, None
    return how, merged
