"""How good a simplification is: measures on drawings given as lists of polylines.

An independent scorer: numpy and shapely only, nothing of ``core``, so that it measures the
code under test rather than sharing its mistakes, and scores any checkout's output alike.
All distances are in the drawings' own units. Drawings are compared through points
sampled along them every ``spacing`` units, so that long segments count by their length.

* coverage(ink, output, tol): fraction of the input ink within ``tol`` of the output
  ("ink kept" at 2% of the diagonal);
* fidelity(output, ink): mean distance of the output to the nearest input ink;
* precision_recall_f(output, reference, tol): the output's share within ``tol`` of the
  reference (precision), the reference's share within ``tol`` of the output (recall), F1
  ("tight recall" is the recall at 0.4% of the diagonal);
* chamfer(a, b): the symmetric Chamfer distance, the mean of both mean nearest distances;
* doubled(output, ink, clusters, diagonal): the share of output ink running beside another
  output stroke over the same intended curve (a line left doubled);
* changed(a, b, tol): the share of either drawing farther than ``tol`` from the other;
* whole_lines(output, reference, diagonal): the share of reference curves of which at
  least 80% of the length lies within 0.6% of the diagonal of ONE output stroke; with
  ``twins``, a curve that lies along another one (80% of it within that 0.6%: the same line
  drawn twice, fitted twice by the reference) counts whole where that one is;
* doubled_on_reference(output, reference, diagonal): the share of the reference's length
  along which two different output strokes run parallel within 1% of the diagonal, away
  from their ends, each nearer that curve than any other; with ``clear``, only along the
  reference farther than that 1% from every other reference curve (away from crossings and
  near-duplicates, where a line a little off its own curve is nearer the other);
* moved(reference, distance): each reference curve moved rigidly by ``distance``, for the
  floor of doubled_on_reference: what it gives a drawing as exact as the reference save
  for that move, where lines go straight through the crossings;
* cluster_reference(ink, clusters, diagonal): for labelled sketches without a reference,
  one line per labelled cluster (medians of its ink binned along its longest stroke), for
  scoring only;
* too_wide(ink, clusters, diagonal): the share of the input ink that no single line can
  keep within 2% of the diagonal (its intended curve drawn wider than 4% across): where a
  sketch is mostly such ink, ink kept and no doubled lines cannot both hold;
* pair_precision_recall(groups, labels): the grouping of strokes against their labels,
  over pairs of strokes (a grouping error told apart from a fitting error);
* wobble(output, reference, diagonal): turning per length against the reference's, at 1%
  of the diagonal; hooks(output, diagonal): the share of ends that turn back more than 90
  degrees in their last 1%; close_parallels_whole(output, reference, diagonal): of the
  reference curves within 1.3% of another along half their length, the share whole.
"""

from __future__ import annotations

import numpy as np
import shapely

__all__ = [
    "changed", "chamfer", "close_parallels_whole", "cluster_reference", "coverage", "doubled",
    "doubled_on_reference", "doubled_samples", "fidelity", "hooks", "moved",
    "nearest_distances", "pair_precision_recall", "precision_recall_f", "sample_points",
    "too_wide", "turning", "whole_lines", "wobble",
]


def _lines(polylines: list[np.ndarray]) -> np.ndarray:
    return np.array([shapely.LineString(p) for p in polylines if len(p) >= 2], dtype=object)


def _samples(polylines: list[np.ndarray], spacing: float
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points every ``spacing`` along each polyline (its end included), the index of the
    polyline each lies on, and the arc length there."""
    keep = [k for k, p in enumerate(polylines) if len(p) >= 2]
    lines = _lines([polylines[k] for k in keep])
    if not len(lines):
        return np.empty((0, 2)), np.empty(0, int), np.empty(0)
    length = shapely.length(lines)
    count = np.ceil(length / spacing).astype(int) + 1
    which = np.repeat(np.arange(len(lines)), count)
    step = length / np.maximum(count - 1, 1)
    at = (np.arange(len(which)) - np.repeat(np.cumsum(count) - count, count)) * step[which]
    points = shapely.get_coordinates(shapely.line_interpolate_point(lines[which], at))
    return points, np.asarray(keep)[which], at


def sample_points(polylines: list[np.ndarray], spacing: float) -> np.ndarray:
    return _samples(polylines, spacing)[0]


def nearest_distances(points: np.ndarray, polylines: list[np.ndarray]) -> np.ndarray:
    """Distance from each point to the nearest of the polylines (inf when there are none)."""
    geoms = _lines(polylines)
    if not len(geoms):
        return np.full(len(points), np.inf)
    pts = shapely.points(points)
    idx = shapely.STRtree(geoms).query_nearest(pts, all_matches=False)[1]
    return shapely.distance(pts, geoms[idx])


def coverage(ink: list[np.ndarray], output: list[np.ndarray], tol: float,
             spacing: float = 1.0) -> float:
    pts = sample_points(ink, spacing)
    return float((nearest_distances(pts, output) <= tol).mean()) if len(pts) else 1.0


def fidelity(output: list[np.ndarray], ink: list[np.ndarray], spacing: float = 1.0) -> float:
    pts = sample_points(output, spacing)
    return float(nearest_distances(pts, ink).mean()) if len(pts) else 0.0


def precision_recall_f(output: list[np.ndarray], reference: list[np.ndarray], tol: float,
                       spacing: float = 1.0) -> tuple[float, float, float]:
    out_pts, ref_pts = sample_points(output, spacing), sample_points(reference, spacing)
    precision = float((nearest_distances(out_pts, reference) <= tol).mean()) if len(
        out_pts) else 0.0
    recall = float((nearest_distances(ref_pts, output) <= tol).mean()) if len(ref_pts) else 0.0
    f = 2 * precision * recall / (precision + recall) if precision + recall > 0 else 0.0
    return precision, recall, f


def chamfer(a: list[np.ndarray], b: list[np.ndarray], spacing: float = 1.0) -> float:
    pa, pb = sample_points(a, spacing), sample_points(b, spacing)
    return float(0.5 * (nearest_distances(pa, b).mean() + nearest_distances(pb, a).mean()))


def too_wide(ink: list[np.ndarray], clusters: list[int], diagonal: float,
             tol_share: float = 0.02) -> float:
    """The share of the input ink that no single line can keep within ``tol_share`` of the
    diagonal: ink where its intended curve was drawn as passes spanning more than twice
    that across. Wherever such ink is kept (:func:`coverage` at the same tolerance), two
    or more output lines run side by side over that curve (:func:`doubled` counts them
    where they lie within 3% of the diagonal of each other): a sketch mostly of such ink
    cannot have both its ink kept and no line doubled.

    The ink is sampled every 0.25% of the diagonal. At each sample, a cross-section square
    to its pass meets the passes of the same intended curve (cluster id) that run along it
    (|cos| >= 0.9, within half a sample step of the section, up to six times the tolerance
    away). Those within twice the tolerance of one another, in a chain from the sample,
    are one bundle here (a wider empty gap can hold two lines, each keeping its side);
    the sample counts when that bundle spans more than twice the tolerance.

    >>> t = np.linspace(0, 400, 41)[:, None]
    >>> passes = [np.hstack([t, 0 * t + 6.0 * k]) for k in range(5)]  # 24 across; 4% is 20
    >>> too_wide(passes, [1] * 5, 500.0), too_wide(passes[:4], [1] * 4, 500.0)
    (1.0, 0.0)
    >>> too_wide(passes, [1, 1, 2, 2, 2], 500.0)  # two curves, each narrow enough
    0.0
    """
    step = 0.0025 * diagonal
    wide = 2 * tol_share * diagonal
    points, which, _ = _samples(ink, step)
    if not len(points):
        return 0.0
    tangents = _tangents(points, which)
    # each intended curve moved apart from the others, so that the query meets its own only
    cluster = np.unique(np.asarray(clusters), return_inverse=True)[1][which]
    apart = points + np.outer(cluster * 10 * (np.ptp(points, axis=0).sum() + 6 * wide), [1, 0])
    geoms = shapely.points(apart)
    i, j = shapely.STRtree(geoms).query(geoms, predicate="dwithin", distance=3 * wide)
    gap = points[j] - points[i]
    along = (gap * tangents[i]).sum(axis=1)
    keep = ((i != j) & (np.abs(along) <= step / 2)
            & (np.abs((tangents[i] * tangents[j]).sum(axis=1)) >= 0.9))
    i, gap = i[keep], gap[keep]
    offset = gap[:, 1] * tangents[i, 0] - gap[:, 0] * tangents[i, 1]
    # each section's offsets with the sample itself at 0, sorted; chains break at wide gaps
    section = np.concatenate([i, np.arange(len(points))])
    offset = np.concatenate([offset, np.zeros(len(points))])
    itself = np.concatenate([np.zeros(len(i), bool), np.ones(len(points), bool)])
    order = np.lexsort((offset, section))
    section, offset, itself = section[order], offset[order], itself[order]
    starts = np.ones(len(section), bool)
    starts[1:] = (section[1:] != section[:-1]) | (np.diff(offset) > wide)
    chain = np.cumsum(starts) - 1
    first = np.flatnonzero(starts)
    last = np.append(first[1:] - 1, len(section) - 1)
    span = offset[last] - offset[first]
    return float((span[chain[itself]] > wide).mean())


def changed(a: list[np.ndarray], b: list[np.ndarray], tol: float, spacing: float) -> float:
    """The larger of: the share of ``a`` farther than ``tol`` from ``b``, and of ``b`` from
    ``a`` (0 for the same drawing, 1 for drawings apart)."""
    pa, pb = sample_points(a, spacing), sample_points(b, spacing)
    far_a = float((nearest_distances(pa, b) > tol).mean()) if len(pa) else 0.0
    far_b = float((nearest_distances(pb, a) > tol).mean()) if len(pb) else 0.0
    return max(far_a, far_b)


def _tangents(points: np.ndarray, which: np.ndarray) -> np.ndarray:
    """Unit tangent at each sample, by differences within its own polyline."""
    nxt = np.minimum(np.arange(len(points)) + 1, len(points) - 1)
    prv = np.maximum(np.arange(len(points)) - 1, 0)
    nxt = np.where(which[nxt] == which, nxt, np.arange(len(points)))
    prv = np.where(which[prv] == which, prv, np.arange(len(points)))
    d = points[nxt] - points[prv]
    n = np.hypot(d[:, 0], d[:, 1])
    return d / np.where(n > 0, n, 1.0)[:, None]


def doubled(output: list[np.ndarray], ink: list[np.ndarray], clusters: list[int],
            diagonal: float) -> float:
    """The share of output ink left doubled (see :func:`doubled_samples`)."""
    _, twin = doubled_samples(output, ink, clusters, diagonal)
    return float(twin.mean()) if len(twin) else 0.0


def doubled_samples(output: list[np.ndarray], ink: list[np.ndarray], clusters: list[int],
                    diagonal: float) -> tuple[np.ndarray, np.ndarray]:
    """The output samples counted, and whether each is doubled.

    Output ink is sampled every 0.25% of the diagonal, leaving out the first and last 3% of
    the diagonal of each stroke. A sample counts as doubled when its nearest sample of
    another output stroke lies within 3% of the diagonal, runs parallel to it
    (|cos| >= 0.9), and lies over the same intended curve: the cluster id of the input ink
    nearest to each of the two samples is the same.
    """
    points, which, at = _samples(output, 0.0025 * diagonal)
    if not len(points):
        return points, np.zeros(0, bool)
    tangents = _tangents(points, which)
    lengths = np.array([shapely.length(shapely.LineString(p)) if len(p) >= 2 else 0.0
                        for p in output])
    end = 0.03 * diagonal
    inner = np.flatnonzero((at >= end) & (at <= lengths[which] - end))
    if not len(inner):
        return points[inner], np.zeros(0, bool)
    geoms = shapely.points(points)
    i, j = shapely.STRtree(geoms).query(geoms[inner], predicate="dwithin",
                                        distance=0.03 * diagonal)
    i = inner[i]
    other = which[i] != which[j]
    i, j = i[other], j[other]
    twin = np.zeros(len(inner), bool)
    if len(i):
        dist = np.hypot(*(points[i] - points[j]).T)
        order = np.lexsort((dist, i))
        first = np.ones(len(order), bool)
        first[1:] = i[order][1:] != i[order][:-1]
        i, j = i[order][first], j[order][first]  # each sample's nearest on another stroke
        parallel = np.abs((tangents[i] * tangents[j]).sum(axis=1)) >= 0.9
        ink_lines = _lines(ink)
        ink_cluster = np.asarray([c for c, p in zip(clusters, ink) if len(p) >= 2])
        tree = shapely.STRtree(ink_lines)
        near_i = ink_cluster[tree.query_nearest(geoms[i], all_matches=False)[1]]
        near_j = ink_cluster[tree.query_nearest(geoms[j], all_matches=False)[1]]
        same = parallel & (near_i == near_j)
        twin[np.searchsorted(inner, i[same])] = True
    return points[inner], twin


def whole_lines(output: list[np.ndarray], reference: list[np.ndarray], diagonal: float,
                tol_share: float = 0.006, share: float = 0.8, twins: bool = False) -> float:
    """The share of reference curves of which at least ``share`` of the length lies within
    ``tol_share`` of the diagonal of ONE output stroke: intended lines that come out whole.
    Curves are sampled every 0.1% of the diagonal. With ``twins``, a curve of which
    ``share`` lies within ``tol_share`` of the diagonal of another reference curve (a line
    drawn twice, fitted twice) counts whole where that one is.

    >>> t = np.linspace(0, 100, 11)[:, None]
    >>> ref = [np.hstack([t, 0 * t]), np.hstack([0 * t, t])]
    >>> whole_lines(ref, ref, 500.0)
    1.0
    >>> whole_lines([ref[0][:6], ref[0][5:], ref[1]], ref, 500.0)  # the first cut in half
    0.5
    >>> twice = ref + [ref[0] + [0, 2.5]]  # the first drawn again 0.5% of 500 below it
    >>> whole_lines([ref[0] - [0, 1], ref[1]], twice, 500.0)  # one line, 1 above: 3.5 off
    0.6666666666666666
    >>> whole_lines([ref[0] - [0, 1], ref[1]], twice, 500.0, twins=True)
    1.0
    """
    points, which, _ = _samples(reference, 0.001 * diagonal)
    if not len(points) or not any(len(p) >= 2 for p in output):
        return 0.0
    tol = tol_share * diagonal
    total = np.bincount(which, minlength=len(reference))
    needed = share * total[:, np.newaxis]
    whole = _whole_curves(points, which, len(reference), output, tol, share)
    if twins:
        own = np.asarray([k for k, p in enumerate(reference) if len(p) >= 2])
        along = _near_counts(points, which, _lines(reference), len(reference), tol,
                             exclude=own) >= needed  # curve r lies along curve own[j]
        whole = whole | (along & whole[own][np.newaxis, :]).any(axis=1)
    curves = total > 0
    return float(whole[curves].mean())


def _whole_curves(points: np.ndarray, which: np.ndarray, n_curves: int,
                  output: list[np.ndarray], tol: float, share: float) -> np.ndarray:
    """For each of ``n_curves`` reference curves (its samples ``points``, labelled
    ``which``), whether at least ``share`` of them lie within ``tol`` of ONE output stroke
    (:func:`whole_lines`' test, curve by curve)."""
    lines = _lines(output)
    if not len(points) or not len(lines):
        return np.zeros(n_curves, bool)
    total = np.bincount(which, minlength=n_curves)
    return (_near_counts(points, which, lines, n_curves, tol)
            >= share * total[:, np.newaxis]).any(axis=1)


def _near_counts(points: np.ndarray, which: np.ndarray, lines: np.ndarray, n_curves: int,
                tol: float, exclude: np.ndarray | None = None) -> np.ndarray:
    """For each curve (its samples ``points``, labelled ``which``), how many of its samples
    lie within ``tol`` of each of ``lines``: shape (curves, lines). ``exclude``: for the
    reference against itself, the curve of each line, whose own samples are not counted."""
    i, k = shapely.STRtree(lines).query(shapely.points(points), predicate="dwithin",
                                        distance=tol)
    if exclude is not None:
        keep = exclude[k] != which[i]
        i, k = i[keep], k[keep]
    n_lines = len(lines)
    per_sample = np.unique(i * n_lines + k)  # each (sample, line) once
    counts = np.bincount(which[per_sample // n_lines] * n_lines + per_sample % n_lines,
                         minlength=n_curves * n_lines)
    return counts.reshape(n_curves, n_lines)


def doubled_on_reference(output: list[np.ndarray], reference: list[np.ndarray],
                         diagonal: float, clear: bool = False) -> float:
    """The share of the reference's length along which two different output strokes run
    parallel to it (|cos| >= 0.9) within 1% of the diagonal, each sample of them away from
    its stroke's ends (3% of the diagonal) and nearer that reference curve than any other.
    With ``clear``, the share of the reference's length farther than 1% of the diagonal
    from every other reference curve: there a drawing a little off the reference is not
    counted doubled for lying nearer another curve (:func:`moved`).

    >>> t = np.linspace(0, 400, 41)[:, None]
    >>> ref = [np.hstack([t, 0 * t])]
    >>> doubled_on_reference(ref, ref, 500.0)
    0.0
    >>> doubled_on_reference([ref[0], ref[0] + [0, 2]], ref, 500.0) > 0.8
    True
    >>> cross = [ref[0], np.hstack([t, 0.05 * t - 10])]  # crossing at a small angle
    >>> doubled_on_reference(moved(cross, 0.5), cross, 500.0) > 0  # the floor
    True
    >>> doubled_on_reference(moved(cross, 0.5), cross, 500.0, clear=True)
    0.0
    """
    step = 0.0025 * diagonal
    rpts, rwhich, _ = _samples(reference, step)
    opts, owhich, oat = _samples(output, step)
    if not len(rpts) or not len(opts):
        return 0.0
    lengths = np.array([shapely.length(shapely.LineString(p)) if len(p) >= 2 else 0.0
                        for p in output])
    end = 0.03 * diagonal
    inner = (oat >= end) & (oat <= lengths[owhich] - end)
    opts, owhich, otan = opts[inner], owhich[inner], _tangents(opts, owhich)[inner]
    if not len(opts):
        return 0.0
    rtan = _tangents(rpts, rwhich)
    rlines = _lines(reference)
    own = np.asarray([k for k, p in enumerate(reference) if len(p) >= 2])
    nearest_curve = own[shapely.STRtree(rlines).query_nearest(shapely.points(opts),
                                                              all_matches=False)[1]]
    r, o = shapely.STRtree(shapely.points(opts)).query(
        shapely.points(rpts), predicate="dwithin", distance=0.01 * diagonal)
    keep = ((nearest_curve[o] == rwhich[r])
            & (np.abs((otan[o] * rtan[r]).sum(axis=1)) >= 0.9))
    r, stroke = r[keep], owhich[o[keep]]
    pairs = np.unique(r * (len(output) + 1) + stroke)
    strokes_per_sample = np.bincount(pairs // (len(output) + 1), minlength=len(rpts))
    counted = np.ones(len(rpts), dtype=bool)
    if clear:
        a, b = shapely.STRtree(rlines).query(shapely.points(rpts), predicate="dwithin",
                                             distance=0.01 * diagonal)
        counted[a[own[b] != rwhich[a]]] = False
        if not counted.any():
            return 0.0
    return float((strokes_per_sample[counted] >= 2).mean())


def moved(reference: list[np.ndarray], distance: float) -> list[np.ndarray]:
    """Each reference curve moved rigidly by ``distance``, curve k in the direction k times
    the golden angle (deterministic, and no two neighbours alike).

    Why: :func:`doubled_on_reference` counts two output strokes near a reference curve,
    each nearer it than any other. Where two curves cross or touch at a small angle, a
    stroke lying a little off its own curve is nearer the other one along a stretch
    (about ``distance`` over the sine of the angle), so any drawing that goes straight
    through such crossings and is not exact counts there; cut at the crossings, the
    stretches fall within its strokes' ends, which the measure leaves out. What the
    reference moved by 0.1% of the diagonal scores is a floor for lines drawn through the
    crossings no closer than that to the reference.

    >>> t = np.linspace(0, 400, 81)[:, None]
    >>> cross = [np.hstack([t, 0 * t]), np.hstack([t, 0.1 * (t - 200)])]  # 6 degrees
    >>> doubled_on_reference(cross, cross, 500.0)
    0.0
    >>> doubled_on_reference(moved(cross, 0.5), cross, 500.0) > 0.01
    True
    """
    angle = np.arange(len(reference)) * np.pi * (3 - np.sqrt(5))
    shift = distance * np.column_stack([np.cos(angle), np.sin(angle)])
    return [np.asarray(p, dtype=float) + shift[k] for k, p in enumerate(reference)]


def cluster_reference(ink: list[np.ndarray], clusters: list[int], diagonal: float
                      ) -> list[np.ndarray]:
    """One line per labelled cluster, for scoring sketches that have labels but no clean
    reference: the cluster's ink projected onto its longest stroke, the median offset in
    bins of 0.5% of the diagonal along it, smoothed over three bins. The simplification
    never reads labels; this only stands in for a drawn reference.

    >>> t = np.linspace(0, 100, 21)[:, None]
    >>> passes = [np.hstack([t, 0 * t + d]) for d in (-1.0, 0.0, 1.0)]
    >>> line, = cluster_reference(passes, [7, 7, 7], 500.0)
    >>> bool(np.abs(line[:, 1]).max() < 1e-9)
    True
    """
    step = 0.005 * diagonal
    out = []
    clusters = np.asarray(clusters)
    for c in np.unique(clusters):
        members = [ink[k] for k in np.flatnonzero(clusters == c) if len(ink[k]) >= 2]
        if not members:
            continue
        lengths = [shapely.length(shapely.LineString(p)) for p in members]
        spine = shapely.LineString(members[int(np.argmax(lengths))])
        if spine.length <= step:
            out.append(np.asarray(spine.coords))
            continue
        count = int(np.ceil(spine.length / step)) + 1
        at = np.linspace(0, spine.length, count)
        axis = shapely.get_coordinates(shapely.line_interpolate_point(spine, at))
        tan = _tangents(axis, np.zeros(count, int))
        normal = np.stack([-tan[:, 1], tan[:, 0]], axis=1)
        pts = sample_points(members, step / 4)
        where = shapely.line_locate_point(spine, shapely.points(pts))
        b = np.clip(np.rint(where / spine.length * (count - 1)).astype(int), 0, count - 1)
        offset = ((pts - axis[b]) * normal[b]).sum(axis=1)
        med = np.zeros(count)
        order = np.argsort(b, kind="stable")
        cuts = np.searchsorted(b[order], np.arange(count + 1))
        for k in range(count):
            part = offset[order[cuts[k]:cuts[k + 1]]]
            med[k] = np.median(part) if len(part) else np.nan
        filled = np.flatnonzero(~np.isnan(med))
        med = np.interp(np.arange(count), filled, med[filled])
        if count >= 3:
            med = np.convolve(np.pad(med, 1, mode="edge"), np.ones(3) / 3, mode="valid")
        out.append(axis + normal * med[:, None])
    return out


def pair_precision_recall(groups: np.ndarray, labels: np.ndarray) -> tuple[float, float]:
    """How well a grouping of strokes matches their labels, over pairs of strokes: the
    share of the pairs put in one group that share a label (precision) and of the pairs
    that share a label put in one group (recall). A stroke in group -1 is in none (it
    pairs with nothing). Precision lost is distinct lines drawn as one; recall lost is
    one line drawn as several. Counted from the table of group against label, never pair
    by pair. Both are 1.0 where there is no pair to judge.

    >>> pair_precision_recall(np.array([0, 0, 1, 1]), np.array([5, 5, 5, 6]))
    (0.5, 0.3333333333333333)
    >>> pair_precision_recall(np.array([0, 1, -1]), np.array([5, 5, 5]))
    (1.0, 0.0)
    """
    groups, labels = np.asarray(groups), np.asarray(labels)
    grouped = groups >= 0

    def pairs(counts: np.ndarray) -> float:
        return float((counts * (counts - 1) / 2).sum())

    _, g = np.unique(groups[grouped], return_inverse=True)
    _, lab = np.unique(labels, return_inverse=True)
    together = pairs(np.bincount(g)) if len(g) else 0.0
    same = pairs(np.bincount(lab))
    cell = g.astype(np.int64) * (lab.max(initial=0) + 1) + lab[grouped]
    both = pairs(np.unique(cell, return_counts=True)[1]) if len(cell) else 0.0
    return (both / together if together else 1.0, both / same if same else 1.0)


def turning(polylines: list[np.ndarray], spacing: float) -> float:
    """Total absolute turning (radians) per unit length of polylines resampled every
    ``spacing``: how much a drawing wanders. Each line's first and last samples turn no
    more than its course does, so a corner counts once, a wiggle as often as it goes.

    >>> t = np.linspace(0, 10, 11)[:, None]
    >>> turning([np.hstack([t, 0 * t])], 1.0)
    0.0
    >>> round(turning([np.hstack([t, 0.3 * np.sin(3 * t)])], 1.0), 2)  # a wiggly line
    0.39
    """
    total, length = 0.0, 0.0
    for p in polylines:
        if len(p) < 2:
            continue
        line = shapely.LineString(p)
        if line.length < 2 * spacing:
            continue
        pts = shapely.get_coordinates(shapely.line_interpolate_point(
            line, np.linspace(0, line.length, int(line.length / spacing) + 1)))
        d = np.diff(pts, axis=0)
        heading = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
        total += float(np.abs(np.diff(heading)).sum())
        length += line.length
    return total / length if length else 0.0


def wobble(output: list[np.ndarray], reference: list[np.ndarray], diagonal: float) -> float:
    """The output's turning per length against the reference's, both resampled every 1%
    of the diagonal: 1.0 turns as the intended curves do, more is wavier.

    >>> t = np.linspace(0, 100, 101)[:, None]
    >>> arc = [np.hstack([t, 0.002 * (t - 50) ** 2])]
    >>> wobble(arc, arc, 200.0)
    1.0
    >>> wobble([arc[0] + np.hstack([0 * t, np.sin(t)])], arc, 200.0) > 2
    True
    """
    ref = turning(reference, 0.01 * diagonal)
    return turning(output, 0.01 * diagonal) / ref if ref > 0 else float("nan")


def hooks(output: list[np.ndarray], diagonal: float, reach: float = 0.01,
          angle: float = 90.0) -> float:
    """The share of open output lines' ends that hook back: turn more than ``angle``
    degrees within their last ``reach`` of the diagonal (a pen's flick kept as a hook).

    >>> t = np.linspace(0, 100, 101)[:, None]
    >>> line = np.hstack([t, 0 * t])
    >>> hooks([line], 500.0)
    0.0
    >>> hooked = np.vstack([line, [[100.0, 2.0], [98.0, 3.0]]])  # turns back at its end
    >>> hooks([hooked], 500.0)
    0.5
    """
    tips = 0
    hooked = 0
    step = reach * diagonal / 4
    for p in output:
        if len(p) < 3 or np.allclose(p[0], p[-1]):
            continue  # a closed line has no end
        line = shapely.LineString(p)
        if line.length < 2 * reach * diagonal:
            continue
        for end in (0, 1):
            at = np.linspace(0, reach * diagonal, 5)
            at = at if end == 0 else line.length - at
            pts = shapely.get_coordinates(shapely.line_interpolate_point(line, at))
            d = np.diff(pts, axis=0)
            d = d[np.hypot(d[:, 0], d[:, 1]) > 1e-9 * step]
            tips += 1
            if len(d) >= 2:
                cos = float(d[0] @ d[-1] / (np.hypot(*d[0]) * np.hypot(*d[-1])))
                hooked += cos < np.cos(np.radians(angle))
    return hooked / tips if tips else 0.0


def close_parallels_whole(output: list[np.ndarray], reference: list[np.ndarray],
                          diagonal: float, near: float = 0.013, share: float = 0.5) -> float:
    """Of the reference curves lying within ``near`` of the diagonal of another reference
    curve along at least ``share`` of their length (close distinct parallels: a rim's
    nested ellipses, a doubled edge), the share that come out whole (:func:`whole_lines`,
    each judged alone); NaN where there is none.

    >>> t = np.linspace(0, 100, 101)[:, None]
    >>> pair = [np.hstack([t, 0 * t]), np.hstack([t, 0 * t + 6.4])]  # 1.28% of 500 apart
    >>> close_parallels_whole(pair, pair, 500.0)
    1.0
    >>> close_parallels_whole([pair[0] + [0, 3.2]], pair, 500.0)  # one line between: none
    0.0
    """
    points, which, _ = _samples(reference, 0.001 * diagonal)
    if not len(points):
        return float("nan")
    own = np.asarray([k for k, p in enumerate(reference) if len(p) >= 2])
    counts = _near_counts(points, which, _lines(reference), len(reference), near * diagonal,
                          exclude=own)
    total = np.bincount(which, minlength=len(reference))
    close = np.flatnonzero((counts >= share * total[:, np.newaxis]).any(axis=1) & (total > 0))
    if not len(close):
        return float("nan")
    return float(_whole_curves(points, which, len(reference), output, 0.006 * diagonal,
                               0.8)[close].mean())  # whole_lines' own tolerance and share
