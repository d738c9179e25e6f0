"""Many polylines at once give, to the bit, what each gives alone."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import shapely

from core import Stroke
from core.arrays import geometry
from core.arrays.geometry import Segments
from core.arrays.polylines import (
    Polylines,
    arc_lengths,
    resample_each,
    resample_polyline,
    resample_polylines,
    starts,
    total_lengths,
)
from core.curves.attributes import NearestInk
from core.merge.fourier import curve_descriptors, fourier_descriptors


def _alone(points: np.ndarray) -> np.ndarray:
    """Arc lengths of one polyline, written out plainly: the reference."""
    s = np.zeros(len(points))
    np.cumsum(np.hypot(*np.diff(points, axis=0).T), out=s[1:])
    return s


def _polylines(seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    lines = [np.cumsum(rng.normal(0, 10.0 ** rng.integers(-4, 0), (k, 2)), axis=0) + rng.random()
             for k in rng.integers(2, 60, 40)]
    lines[3] = np.repeat(lines[3][:3], 2, axis=0)  # repeated points: zero-length steps
    lines.append(np.zeros((2, 2)))  # no length at all
    lines.append(rng.random((500, 2)))  # one much longer than the rest
    return lines


@pytest.mark.parametrize("long_one", [True, False])  # rows padded in groups, or in one
def test_arc_lengths_of_many_are_each_ones_own(long_one):
    lines = _polylines(0)[:None if long_one else -1]
    sizes = np.array([len(p) for p in lines])
    first = starts(sizes)
    together = arc_lengths(np.concatenate(lines), first, first + sizes - 1)
    alone = [_alone(p) for p in lines]
    for p, s in zip(lines, alone):
        np.testing.assert_array_equal(arc_lengths(p), s)
    np.testing.assert_array_equal(together, np.concatenate(alone))
    np.testing.assert_array_equal(total_lengths(lines), [s[-1] for s in alone])


@pytest.mark.parametrize("queries", [300, 5000])  # few on each polyline, and many
def test_sampling_many_is_np_interp_of_each(queries):
    lines = _polylines(1)
    arcs = [_alone(p) for p in lines]
    lines_ = Polylines.of(arcs, lines)
    rng = np.random.default_rng(2)
    which = np.sort(rng.integers(0, len(lines), queries))  # grouped by polyline
    # inside, outside, and exactly on the points of each polyline
    t = np.array([rng.uniform(-0.1, 1.1) * arcs[k][-1] for k in which])
    t[::3] = [arcs[k][rng.integers(len(arcs[k]))] for k in which[::3]]
    got = lines_.at(which, t)
    for k in range(len(lines)):
        mine = which == k
        want = np.c_[np.interp(t[mine], arcs[k], lines[k][:, 0]),
                     np.interp(t[mine], arcs[k], lines[k][:, 1])]
        np.testing.assert_array_equal(got[mine], want)
        index = lines_.index(which[mine], t[mine]) - lines_.first[k]
        np.testing.assert_array_equal(
            index, np.minimum(np.searchsorted(arcs[k], t[mine]), len(arcs[k]) - 1))


def test_descriptors_of_many_are_each_ones_own():
    lines = _polylines(3)
    for describe in (fourier_descriptors, curve_descriptors):
        together = describe(lines)
        for line, row in zip(lines, together):
            np.testing.assert_array_equal(row, describe([line])[0])


def _end_direction(points: np.ndarray, reach: float) -> np.ndarray:
    """Unit direction leaving the first point, looking ``reach`` along: one at a time."""
    s = _alone(points)
    k = int(np.clip(np.searchsorted(s, reach), 1, len(points) - 1))
    d = points[k] - points[0]
    n = np.hypot(*d)
    return d / n if n > 0 else d


@pytest.mark.parametrize("spacing", [1e-3, 0.05, 3.0])
def test_resampling_many_is_each_ones_own(spacing):
    lines = _polylines(4)
    lines.append(np.array([[0.0, 0], [1, 0], [1, 1], [0, 0]]))  # closed: kept a loop
    sizes = np.array([len(p) for p in lines])
    points, new_sizes = resample_polylines(np.concatenate(lines), sizes, spacing)
    alone = [resample_polyline(p, spacing) for p in lines]
    np.testing.assert_array_equal(new_sizes, [len(a) for a in alone])
    assert points.tobytes() == np.concatenate(alone).tobytes()
    assert len(alone[-1]) >= 4


def test_where_points_come_nearest_along_segments_is_geos_answer_to_the_bit():
    rng = np.random.default_rng(0)
    segs = Segments.of([rng.uniform(0, 1, (rng.integers(2, 30), 2)) for _ in range(100)])
    seg = rng.integers(0, len(segs.start), 20_000)
    points = rng.uniform(-0.2, 1.2, (20_000, 2))  # beyond the ends too
    assert (segs.along(seg, points)
            == shapely.line_locate_point(segs.lines[seg], shapely.points(points))).all()


@pytest.mark.parametrize("seed", range(3))
def test_the_lines_a_reach_finds_whole_are_those_its_single_segments_find(seed):
    """``Segments.whole`` (one LineString per polyline) against the tree of single
    segments: the same (point, polyline) pairs within every reach, with polylines of one
    point (no segment) among them, points on the lines and on a grid."""
    rng = np.random.default_rng(seed)
    lines = [rng.integers(0, 8, (rng.integers(1, 15), 2)).astype(float) for _ in range(12)]
    lines += _polylines(seed)[:6]
    segs = Segments.of(lines)
    tree, number = segs.whole
    points = shapely.points(np.concatenate([rng.integers(-1, 9, (300, 2)).astype(float),
                                            rng.uniform(-1, 9, (300, 2))]))
    for reach in (0.0, 0.5, 1.0, 2.5):
        i, k = tree.query(points, predicate="dwithin", distance=reach)
        j, seg = segs.tree.query(points, predicate="dwithin", distance=reach)
        whole = set(zip(i.tolist(), number[k].tolist()))
        assert len(whole) == len(i) and whole == set(zip(j.tolist(), segs.polyline[seg].tolist()))


@pytest.mark.parametrize("seed", range(4))
def test_a_small_nearest_query_finds_the_segment_a_tree_finds(seed, monkeypatch):
    """Measured pair by pair (few points against few segments), the nearest segment is the
    one GEOS's tree query finds, ties to the lowest numbered: on a grid, where many points
    lie equally near two segments, with repeated points (segments of no length), and on
    wandering lines at many scales."""
    rng = np.random.default_rng(seed)
    for k in range(60):
        if k % 2:
            lines = [rng.integers(0, 6, (rng.integers(2, 12), 2)).astype(float) for _ in range(3)]
            points = rng.integers(-1, 7, (40, 2)).astype(float)
        else:
            lines = _polylines(seed * 100 + k)[:3]
            flat = np.concatenate(lines)
            points = flat[rng.integers(0, len(flat), 30)] + rng.normal(0, 1e-3, (30, 2))
        segs = Segments.of(lines)
        assert len(points) * len(segs.start) <= geometry.BRUTE_PAIRS
        small = segs.nearest(points)
        monkeypatch.setattr(geometry, "BRUTE_PAIRS", 0)
        tree = segs.nearest(points)
        monkeypatch.undo()
        assert small[0].tolist() == tree[0].tolist()
        assert small[1].tobytes() == tree[1].tobytes()


def test_ink_passing_a_segment_too_short_for_geos_is_found_at_the_stroke_start():
    """Points 1e-300 apart are distinct to the cleaning, but GEOS cannot locate a point on
    the segment between them (found by a hostile sketch: a RuntimeWarning and NaN, or
    GEOSException on a single segment)."""
    line = np.array([[0.0, 0.38], [1e-300, 0.38], [1.0, 0.38]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rows = NearestInk([Stroke(line)], [line]).passing(np.array([[0.0173, 0.3832]]), 0.1)
    stroke, at = rows.of(0)
    assert stroke.tolist() == [0, 0] and at.tolist() == [0.0, pytest.approx(0.0173)]


@pytest.mark.parametrize("seed", range(4))
def test_the_nearest_row_of_each_sample_is_the_first_after_sorting_the_rows(seed):
    """`nearest_of_each` against the sort it stands in for: rows of a query (sample,
    distance, segment), with ties in distance, given by sample (as a tree gives them; the
    segments of each in any order) and shuffled."""
    rng = np.random.default_rng(seed)
    i = np.sort(rng.integers(0, 50, 600))
    seg = rng.integers(0, 40, 600)
    i, seg = np.unique(np.stack([i, seg], axis=1), axis=0).T  # each pair once
    dist = rng.integers(0, 5, len(i)).astype(float)  # many ties
    for rows in (np.lexsort((rng.random(len(i)), i)), rng.permutation(len(i))):
        a, d, s = i[rows], dist[rows], seg[rows]
        order = np.lexsort((s, d, a))
        want = order[np.r_[True, a[order][1:] != a[order][:-1]]]
        assert geometry.nearest_of_each(a, d, s).tolist() == want.tolist()


@pytest.mark.parametrize("seed", range(3))
def test_reached_through_segments_is_reached_through_whole_lines_and_by_brute_force(seed):
    """`Reached.of` asked through `Segments` (their single segments' tree) gives the same
    (sample, line) pairs as through the lines whole, each pair once, and both the pairs a
    brute-force measure of every sample against every segment finds; dots and lines of
    one point among the lines keep their numbers."""
    rng = np.random.default_rng(seed)
    lines = [np.cumsum(rng.normal(0, 0.05, (rng.integers(2, 40), 2)), axis=0) + rng.random(2)
             for _ in range(12)]
    polylines = [np.cumsum(rng.normal(0, 0.05, (rng.integers(1, 30), 2)), axis=0)
                 + rng.random(2) for _ in range(8)]
    reach, spacing = 0.08, 0.03
    whole = geometry.Reached.of(polylines, lines, reach, spacing)
    asked = [np.zeros((1, 2)) + 9.0] + lines  # a lone point first: numbers shift by one
    through = geometry.Reached.of(polylines, Segments.of(asked), reach, spacing)
    pairs = sorted(zip(whole.sample.tolist(), whole.line.tolist()))
    assert sorted(zip(through.sample.tolist(), (through.line - 1).tolist())) == pairs
    assert len(set(pairs)) == len(pairs)
    points = resample_each(polylines, spacing)[0]
    segs = Segments.of(lines)
    d = geometry.segment_distance(points[:, None], segs.origin[None], segs.end[None])
    near = d <= reach
    brute = sorted({(int(p), int(segs.polyline[s])) for p, s in zip(*np.nonzero(near))})
    assert pairs == brute
    assert whole.count.tolist() == through.count.tolist()
