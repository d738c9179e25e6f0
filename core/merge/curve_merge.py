"""Curve-curve merging: when two curves depict one stroke, and the curve that replaces them.

Two curves are neighbours (paper 3.2.2, with d_eps = alpha * D and d_theta = ``angle``)
when they run side by side or continue each other:

* side by side: most of the shorter curve lies within d_eps of the longer one and their
  tangents there differ by less than d_theta (checked along the whole overlap, not at the
  single closest pair of points, which a narrow V shape would pass);
* overlapping (beyond the paper): the shorter runs beside the longer at one of its ends,
  for at least d_eps, then carries on past that end: a stroke drawn on from where the last
  one ended, a little over it. Neither side by side (too little of it alongside) nor end to
  end (its end lies beside the other's middle), such a pair was left doubled over the
  overlap (docs/decisions.md, "Where each tuned number comes from");
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

from ..arrays.geometry import unit_rows
from ..arrays.polylines import (
    Polylines,
    arc_lengths,
    leading_count,
    resample_polylines,
    split,
    starts,
)
from ..params import Tuning

__all__ = [
    "PROBE_SLACK", "continues", "pair_and_merge", "pair_and_merge_many", "sample_spacing",
    "SampledCurve",
]

#: a screen before the exact side-by-side test: a pair with fewer of its nine probe points
#: within d_eps than ``side_share`` less this is refused unmeasured (the probes sample the
#: shorter curve coarsely; the exact test decides the rest)
PROBE_SLACK = 0.2


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
    def many(cls, polylines: list[np.ndarray], spacing: float | None = None
             ) -> list[SampledCurve]:
        """Polylines resampled evenly at ``spacing`` (as by
        :func:`core.arrays.polylines.resample_polyline`; None: already resampled), all at
        once."""
        if not polylines:
            return []
        sizes = np.fromiter(map(len, polylines), dtype=np.intp, count=len(polylines))
        points = np.concatenate(polylines)
        if spacing is not None:
            points, sizes = resample_polylines(points, sizes, spacing)
        first = starts(sizes)
        last = first + sizes - 1
        s = arc_lengths(points, first, last)
        d = np.empty_like(points)  # central differences, one-sided at each end
        d[1:-1] = (points[2:] - points[:-2]) / 2
        d[first] = points[first + 1] - points[first]
        d[last] = points[last] - points[last - 1]
        tangents = unit_rows(d)
        lines = shapely.linestrings(points, indices=np.repeat(np.arange(len(sizes)), sizes))
        # copies: a view would keep the whole batch while any one curve lives
        return [cls(points[a:b].copy(), s[a:b].copy(), tangents[a:b].copy(), line)
                for a, b, line in zip(first.tolist(), (last + 1).tolist(), lines)]

    @cached_property
    def length(self) -> float:
        return float(self.s[-1])

    @cached_property
    def ends(self) -> np.ndarray:
        """First point, first tangent, last point, last tangent, as one row of 8."""
        return np.concatenate([self.points[0], self.tangents[0], self.points[-1],
                               self.tangents[-1]])

    @cached_property
    def point_geoms(self) -> np.ndarray:
        """The points as shapely Points, made once: a curve is measured against many."""
        return shapely.points(self.points)


def continues(a: SampledCurve, b: SampledCurve, d_eps: float, cos_max: float) -> bool:
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



@lru_cache(maxsize=4096)
def _probe_index(n: int) -> np.ndarray:
    """Nine indices spread evenly over n points, ends included."""
    return np.linspace(0, n - 1, 9).astype(int)


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.minimum(np.maximum(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


def _project(bases: list[SampledCurve], curves: list[SampledCurve]
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, Polylines]:
    """Arc-length parameter of the points of each ``curves[k]`` along ``bases[k]``,
    extended linearly past its ends, and their distance to it, for all the points at once.

    Returns s, the distances, which pair each point belongs to, and the bases as one
    :class:`Polylines`."""
    sizes = np.fromiter((len(c.points) for c in curves), dtype=np.intp, count=len(curves))
    which = np.repeat(np.arange(len(curves)), sizes)
    pts = np.concatenate([c.points for c in curves])
    lines = np.array([b.line for b in bases], dtype=object)
    s = shapely.line_locate_point(lines[which], np.concatenate([c.point_geoms for c in curves]))
    bases_ = Polylines.of([b.s for b in bases], [b.points for b in bases])
    # the closest point is where the line is at s: cheaper than GEOS measuring again
    off = pts - bases_.at(which, s)
    dist = np.hypot(off[:, 0], off[:, 1])
    ends = np.array([b.ends for b in bases])[which]
    before = (pts[:, 0] - ends[:, 0]) * ends[:, 2] + (pts[:, 1] - ends[:, 1]) * ends[:, 3]
    after = (pts[:, 0] - ends[:, 4]) * ends[:, 6] + (pts[:, 1] - ends[:, 5]) * ends[:, 7]
    length = bases_.s[bases_.last][which]
    s = np.where((s <= 1e-12) & (before < 0), before, s)
    s = np.where((s >= length - 1e-12) & (after > 0), length + after, s)
    return s, dist, which, bases_


def _side_by_side(longs: list[SampledCurve], shorts: list[SampledCurve], d_eps: float,
                  cos_max: float, share: float) -> tuple[np.ndarray, list[np.ndarray]]:
    """Whether each short curve runs beside its long one (at least ``share`` of it within
    d_eps, their tangents there mostly within the angle), and the short curves' parameters
    along the long ones."""
    s, dist, which, bases_ = _project(longs, shorts)
    sizes = np.bincount(which, minlength=len(shorts))
    near = dist <= d_eps
    count = np.bincount(which[near], minlength=len(shorts))
    side = count / sizes >= share
    # the median |cos| of the tangent angle over each pair's near points
    tangents = np.concatenate([c.tangents for c in shorts])[near]
    long_tangents = np.concatenate([c.tangents for c in longs])
    w = which[near]
    idx = bases_.index(w, s[near])
    cos = np.abs(tangents[:, 0] * long_tangents[idx, 0] + tangents[:, 1] * long_tangents[idx, 1])
    cos = cos[np.lexsort((cos, w))]
    has = count > 0
    mid = (starts(count) + count // 2)[has]
    median = np.zeros(len(shorts))
    median[has] = (cos[mid - 1 + count[has] % 2] + cos[mid]) / 2  # odd: (x + x) / 2 = x
    side &= median >= cos_max
    return side, split(s, sizes)


def _staggered(longs: list[SampledCurve], shorts: list[SampledCurve], d_eps: float,
               cos_max: float) -> tuple[np.ndarray, list[np.ndarray]]:
    """Whether each short curve carries on from an end of its long one after running beside
    it for a while (a stroke drawn on from where the last one ended, overlapping it): the
    short curve's points within d_eps of the long one are one run at one of its ends, at
    least d_eps long, their tangents within the angle, and the rest of it lies past one end
    of the long curve. Returns that, and the short curves' parameters along the long ones."""
    s, dist, which, bases_ = _project(longs, shorts)
    sizes = np.bincount(which, minlength=len(shorts))
    ok = np.zeros(len(shorts), dtype=bool)
    long_tangents = np.concatenate([c.tangents for c in longs])
    for k, (s_k, d_k, short, long_) in enumerate(zip(split(s, sizes), split(dist, sizes),
                                                    shorts, longs)):
        near, arc, tan_s = d_k <= d_eps, short.s, short.tangents
        run = leading_count(near)
        if run == 0:  # the near run, if any, is at the other end: walk the short one back
            near, s_k, arc, tan_s = near[::-1], s_k[::-1], arc[-1] - arc[::-1], -tan_s[::-1]
            run = leading_count(near)
        if run == 0 or run == len(near) or near[run:].any() or arc[run - 1] < d_eps:
            continue
        far = s_k[run:]
        if not ((far > long_.length).all() or (far < 0).all()):
            continue
        if np.any(np.diff(s_k) * np.sign(far[0] - s_k[0]) < -d_eps / 4):
            continue  # turns back on itself
        idx = bases_.index(np.full(run, k), np.clip(s_k[:run], 0, long_.length))
        cos = np.abs((tan_s[:run] * long_tangents[idx]).sum(axis=1))
        ok[k] = np.median(cos) >= cos_max
    return ok, split(s, sizes)


def _blend(pairs: list[tuple[SampledCurve, float, SampledCurve, float, np.ndarray]],
           d_eps: float) -> list[np.ndarray]:
    """The merged polyline of each (long, its weight, short, its weight, the short's
    parameters along the long): the weighted middle where they overlap, each alone where it
    does not, blended over d_eps."""
    n_pairs = len(pairs)
    scalars = np.empty((n_pairs, 7))  # lo, step, end_l, start_s, end_s, w_l, w_s
    counts = np.empty(n_pairs, dtype=np.intp)
    shorts, arcs = [], []
    for k, (long_, wl, short, ws, s_s) in enumerate(pairs):
        pts_s = short.points
        if s_s[-1] < s_s[0]:
            pts_s, s_s = pts_s[::-1], s_s[::-1]
        s_s = np.maximum.accumulate(s_s)
        end_l, start_s, end_s = long_.length, float(s_s[0]), float(s_s[-1])
        spacing = float(long_.s[1] - long_.s[0]) if len(long_.s) > 1 else sample_spacing(d_eps)
        lo, hi = min(0.0, start_s), max(end_l, end_s)
        n = max(2, math.ceil((hi - lo) / spacing) + 1)
        counts[k] = n
        scalars[k] = (lo, (hi - lo) / (n - 1), end_l, start_s, end_s, wl, ws)
        shorts.append(pts_s)
        arcs.append(s_s)
    which = np.repeat(np.arange(n_pairs), counts)
    first = starts(counts)
    lo, step, end_l, start_s, end_s, wl, ws = scalars[which].T
    t = (np.arange(len(which)) - first[which]) * step + lo  # np.linspace, made directly
    last = first + counts - 1
    t[last] = np.maximum(scalars[:, 2], scalars[:, 4])
    in_l = (t >= 0) & (t <= end_l)
    in_s = (t >= start_s) & (t <= end_s)
    w_l = wl * in_l * (1e-3 + _smoothstep(np.minimum(t, end_l - t) / d_eps))
    w_s = ws * in_s * (1e-3 + _smoothstep(np.minimum(t - start_s, end_s - t) / d_eps))
    pl = Polylines.of([p[0].s for p in pairs], [p[0].points for p in pairs]).at(which, t)
    ps = Polylines.of(arcs, shorts).at(which, t)
    point = scalars[:, 4] <= scalars[:, 3]  # the short curve projects to one point
    if point.any():
        rows = point[which]
        ps[rows] = np.array([p[0] for p in shorts])[which[rows]]
    total = w_l + w_s
    keep = total > 0
    merged = (w_l[:, None] * pl + w_s[:, None] * ps)[keep] / total[keep][:, None]
    which = which[keep]
    d = merged[1:] - merged[:-1]
    moves = np.empty(len(merged), dtype=bool)
    moves[:1] = True
    np.greater(np.hypot(d[:, 0], d[:, 1]), 1e-12, out=moves[1:])
    moves[1:] |= which[1:] != which[:-1]
    merged, which = merged[moves], which[moves]
    return split(merged, np.bincount(which, minlength=n_pairs))


def _within(merged: list[np.ndarray], parents: list[tuple[SampledCurve, SampledCurve]],
            d_eps: float) -> np.ndarray:
    """Whether every point of both parents lies within d_eps of their merged polyline."""
    if len(merged) == 1:
        lines = np.array([shapely.linestrings(merged[0])])
    else:
        lines = shapely.linestrings(np.concatenate(merged), indices=np.repeat(
            np.arange(len(merged)), [len(m) for m in merged]))
    geoms = [g for a, b in parents for g in (a.point_geoms, b.point_geoms)]
    sizes = np.fromiter(map(len, geoms), dtype=np.intp, count=len(geoms))
    near = shapely.dwithin(np.concatenate(geoms), np.repeat(np.repeat(lines, 2), sizes), d_eps)
    every = np.logical_and.reduceat(near, starts(sizes))
    return every[0::2] & every[1::2]


def pair_and_merge_many(pairs: list[tuple[SampledCurve, float, SampledCurve, float]],
                        d_eps: float, max_angle_deg: float, end_to_end: bool = True,
                        side_share: float = Tuning.side_share
                        ) -> list[tuple[str | None, np.ndarray | None]]:
    """How each pair of weighted curves pairs ('side', 'overlap', 'end' or None; no 'end'
    unless ``end_to_end``) and, if it does, their merged polyline. Side by side means at
    least ``side_share`` of the shorter within d_eps of the longer.

    The merged polyline keeps within d_eps of both curves, or the pair is refused. The
    pairs are worked out together, a step at a time for all (the merge loop costs hundreds
    of pairs at once, and each step is a few vectorised calls however many there are).
    """
    cos_max = math.cos(math.radians(max_angle_deg))
    ordered = [(a, wa, b, wb) if a.length >= b.length else (b, wb, a, wa)
               for a, wa, b, wb in pairs]
    how: list[str | None] = [None] * len(pairs)
    live = [k for k, (a, _, b, _) in enumerate(pairs) if not _straight_and_askew(a, b, cos_max)]
    # a few points first: most candidate pairs only touch at a node and are refused here
    along: dict[int, np.ndarray] = {}  # the short curve's parameters along the long one
    end_probed: list[int] = []  # pairs where an end of the short curve lies by the long one
    if live:
        probes = np.concatenate([ordered[k][2].point_geoms[_probe_index(
            len(ordered[k][2].points))] for k in live])
        lines = np.array([ordered[k][0].line for k in live], dtype=object)
        near = shapely.dwithin(probes, np.repeat(lines, 9), d_eps).reshape(-1, 9)
        probed = [k for k, hits in zip(live, np.count_nonzero(near, axis=1).tolist())
                  if hits / 9 >= side_share - PROBE_SLACK]
        end_probed = [k for k, row in zip(live, near.tolist())
                      if (row[0] or row[-1]) and sum(row) >= 2]
        if probed:
            side, s = _side_by_side([ordered[k][0] for k in probed],
                                    [ordered[k][2] for k in probed], d_eps, cos_max,
                                    side_share)
            for k, beside, s_k in zip(probed, side.tolist(), s):
                along[k] = s_k
                how[k] = "side" if beside else None
    tails = [k for k in end_probed if how[k] is None]
    if tails:
        stag, s = _staggered([ordered[k][0] for k in tails],
                             [ordered[k][2] for k in tails], d_eps, cos_max)
        for k, yes, s_k in zip(tails, stag.tolist(), s):
            if yes:
                how[k], along[k] = "overlap", s_k
    if end_to_end:
        ends = [k for k in live if how[k] is None
                and continues(pairs[k][0], pairs[k][2], d_eps, cos_max)]
        fresh = [k for k in ends if k not in along]
        if fresh:
            s = _project([ordered[k][0] for k in fresh], [ordered[k][2] for k in fresh])[0]
            sizes = np.array([len(ordered[k][2].points) for k in fresh])
            along.update(zip(fresh, split(s, sizes)))
        for k in ends:
            how[k] = "end"
    paired = [k for k in range(len(pairs)) if how[k] is not None]
    out: list[tuple[str | None, np.ndarray | None]] = [(None, None)] * len(pairs)
    if not paired:
        return out
    merged = _blend([(*ordered[k], along[k]) for k in paired], d_eps)
    enough = [(k, m) for k, m in zip(paired, merged) if len(m) >= 2]
    if enough:
        within = _within([m for _, m in enough], [(pairs[k][0], pairs[k][2]) for k, _ in enough],
                         d_eps)
        for (k, m), ok in zip(enough, within.tolist()):
            if ok:
                out[k] = (how[k], m.copy())  # a copy: a view would keep the whole batch
    return out


def pair_and_merge(a: SampledCurve, wa: float, b: SampledCurve, wb: float, d_eps: float,
                   max_angle_deg: float, end_to_end: bool = True
                   ) -> tuple[str | None, np.ndarray | None]:
    """:func:`pair_and_merge_many` of one pair."""
    return pair_and_merge_many([(a, wa, b, wb)], d_eps, max_angle_deg, end_to_end)[0]
