"""Base complex: exact counts and adjacency on drawings whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from helpers import circle, square
from hypothesis import given, settings
from hypothesis import strategies as st

from core import build_base_complex
from core.arrays.geometry import lines_from
from core.complex.base_complex import BaseComplexError, check_euler


def build(*strokes):
    return build_base_complex([np.asarray(s, dtype=float) for s in strokes])


def counts(cx):
    return cx.num_nodes, cx.num_curves, cx.num_patches, cx.num_components


def curve_at(cx, point):
    """The id of the curve passing nearest to a point."""
    d = shapely.distance(lines_from(cx.curves), shapely.Point(point))
    return int(np.argmin(d))


def patch_at(cx, point):
    hits = [i for i in range(cx.num_patches)
            if cx.patch_polygon(i).contains(shapely.Point(point))]
    assert len(hits) == 1, hits
    return hits[0]


def overshooting_side(a, b, overshoot=0.1):
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = (b - a) / np.linalg.norm(b - a)
    return np.array([a - overshoot * d, b + overshoot * d])


def short_crossing(at, direction, length=0.2, angle_deg=12.0):
    """A short straight stroke crossing a side at ``at`` at a shallow angle."""
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    c, s = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    r = np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
    return np.array([at - r * length / 2, at + r * length / 2])


def test_paper_triangle_drawn_with_seven_strokes():
    a, b, c = np.array([0, 0.0]), np.array([1, 0.0]), np.array([0.5, 0.8])
    x = np.linspace(0.2, 0.45, 30)
    arc = np.stack([x, 0.01 - 0.03 * np.sin(np.pi * (x - 0.2) / 0.25) ** 0.5 * 1.0], axis=1)
    arc[:, 1] = 0.01 - 0.03 * (1 - ((x - 0.325) / 0.125) ** 2)  # dips below AB and back
    strokes = [
        overshooting_side(a, b), overshooting_side(b, c), overshooting_side(c, a),
        short_crossing((b + c) / 2, c - b), short_crossing((c + a) / 2, a - c),
        short_crossing(np.array([0.75, 0.0]), b - a), arc,
    ]
    cx = build(*strokes)
    # 3 corners + 6 overshoot tails; 3 crossings x 3 nodes; 2 arc crossings + 2 arc ends
    assert counts(cx) == (22, 23, 2, 1)
    triangle = patch_at(cx, (0.5, 0.3))
    sliver = 1 - triangle
    assert len(cx.patches[triangle].boundary) == 8  # AB in 4 pieces, BC and CA in 2 each
    assert len(cx.patches[sliver].boundary) == 2  # the arc's middle and the AB piece above it
    assert cx.patches[triangle].holes == [] and cx.patches[sliver].holes == []
    shared = curve_at(cx, (0.325, 0.0))
    assert cx.patches_of_curve(shared) == sorted([triangle, sliver])
    inner_tail = curve_at(cx, (0.84, 0.018))  # the crossing stroke's end inside the triangle
    assert cx.patches_of_curve(inner_tail) == [triangle]
    assert tuple(cx.curve_patches[inner_tail]) == (triangle, triangle)  # a spike
    assert cx.patches_of_curve(curve_at(cx, (1.08, 0.0))) == []  # an overshoot tail
    assert cx.patches[triangle].area == pytest.approx(0.4, abs=0.01)
    corner = int(np.argmin(np.hypot(*(cx.nodes - b).T)))
    assert len(cx.node_curves[corner]) == 4


def test_square_with_overshooting_sides():
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]
    cx = build(*[overshooting_side(corners[i], corners[(i + 1) % 4]) for i in range(4)])
    assert counts(cx) == (12, 12, 1, 1)
    degree = np.bincount(cx.curve_nodes.ravel())
    assert sorted(degree.tolist()) == [1] * 8 + [4] * 4
    ring = cx.patches[0].boundary
    assert len(ring) == 4 and cx.patches[0].area == pytest.approx(1.0)
    assert all(cx.patches_of_curve(c) == [0] for c, _ in ring)
    # the ring is walked counter-clockwise and is closed
    pts = cx.ring_points(ring)
    assert shapely.Polygon(pts).exterior.is_ccw


def test_two_overlapping_circles():
    cx = build(circle(0, 0, 1), circle(1, 0, 1))
    assert counts(cx) == (2, 4, 3, 1)
    assert not cx.node_is_auxiliary.any()
    lens = patch_at(cx, (0.5, 0))
    left, right = patch_at(cx, (-0.5, 0)), patch_at(cx, (1.5, 0))
    assert len({lens, left, right}) == 3
    assert len(cx.patches[lens].boundary) == 2
    assert all(len(cx.node_curves[n]) == 4 for n in range(2))
    # each of the lens's arcs separates it from one lune
    for c, _ in cx.patches[lens].boundary:
        assert len(cx.patches_of_curve(c)) == 2


def test_figure_eight_self_intersection():
    t = np.linspace(np.pi / 2, np.pi / 2 + 2 * np.pi, 400)
    eight = np.stack([np.sin(t), np.sin(t) * np.cos(t)], axis=1)
    cx = build(eight)
    assert counts(cx) == (1, 2, 2, 1)
    np.testing.assert_allclose(cx.nodes[0], [0, 0], atol=1e-5)
    assert cx.node_curves == [[0, 1]]
    assert sorted(len(cx.patches_of_curve(c)) for c in range(2)) == [1, 1]


def test_lone_closed_loop_gets_one_auxiliary_node():
    cx = build(circle(0, 0, 1))
    assert counts(cx) == (1, 1, 1, 1)
    assert cx.node_is_auxiliary.tolist() == [True]
    assert tuple(cx.curve_nodes[0]) == (0, 0)
    assert cx.patches[0].area == pytest.approx(np.pi, rel=1e-3)


def test_square_inside_a_square_is_a_hole():
    cx = build(square(0, 0, 1), square(0.25, 0.25, 0.5))
    assert counts(cx) == (2, 2, 2, 2)
    outer, inner = patch_at(cx, (0.1, 0.1)), patch_at(cx, (0.5, 0.5))
    assert len(cx.patches[outer].holes) == 1 and cx.patches[inner].holes == []
    assert cx.patches[outer].area == pytest.approx(0.75)
    inner_curve = curve_at(cx, (0.25, 0.5))
    assert cx.patches_of_curve(inner_curve) == sorted([outer, inner])
    assert cx.patches_of_curve(curve_at(cx, (0, 0.5))) == [outer]
    assert cx.patch_polygon(outer).area == pytest.approx(0.75)


def test_collinear_overlapping_strokes_become_one_curve():
    cx = build([[0, 0], [2, 0]], [[1, 0], [3, 0]])
    assert counts(cx) == (2, 1, 0, 1)
    np.testing.assert_allclose(cx.curves[0][[0, -1]][:, 0].tolist(), sorted([0, 3])
                               if cx.curves[0][0, 0] == 0 else [3, 0])
    crossed = build([[0, 0], [2, 0]], [[1, 0], [3, 0]], [[1.5, -1], [1.5, 1]])
    assert counts(crossed) == (5, 4, 0, 1)
    total = sum(shapely.length(lines_from(crossed.curves)))
    assert total == pytest.approx(3 + 2)  # no coincident double curve


def test_empty_input_gives_an_empty_complex():
    cx = build_base_complex([])
    assert counts(cx) == (0, 0, 0, 0)


def test_euler_check_fails_loudly():
    cx = build(square(0, 0, 1))
    cx.patches.append(cx.patches[0])
    with pytest.raises(BaseComplexError, match="Euler"):
        check_euler(cx)


coords = st.floats(0, 1, allow_nan=False, allow_infinity=False)
polyline = st.lists(st.tuples(coords, coords), min_size=2, max_size=6)


@settings(max_examples=150, deadline=None)
@given(st.lists(polyline, min_size=1, max_size=12))
def test_random_sketches_form_a_planar_subdivision(raw):
    strokes = [np.array(s) for s in raw]
    strokes = [s for s in strokes if np.ptp(s, axis=0).max() > 0]
    if not strokes:
        return
    cx = build_base_complex(strokes)  # checks Euler's formula itself
    assert cx.euler_characteristic() == cx.num_components
    # every curve borders at most two patches, and every patch ring uses its curves
    assert cx.curve_patches.shape == (cx.num_curves, 2)
    for p, patch in enumerate(cx.patches):
        assert patch.area > 0
        for c in patch.curves():
            assert p in cx.curve_patches[c]
    # an independent count of the bounded faces: GEOS polygonize on the same noded curves
    faces = shapely.get_parts(shapely.polygonize(lines_from(cx.curves)))
    assert len(faces) == cx.num_patches
    assert sum(p.area for p in cx.patches) == pytest.approx(shapely.area(faces).sum(), abs=1e-9)


def test_crossing_count_is_exact_past_the_limit_and_none_within_it():
    # a grid of 12 horizontal and 12 vertical lines: 144 proper crossings, while a fan of
    # 200 parallel diagonals has thousands of overlapping boxes and no crossing at all
    from core.complex.noding import more_crossings_than

    t = np.linspace(0, 11, 12)
    grid = [np.array([[-1, y], [12, y]]) for y in t] + [np.array([[x, -1], [x, 12]]) for x in t]
    fan = [np.array([[0, k * 0.01], [10, 10 + k * 0.01]]) for k in range(200)]
    assert more_crossings_than(grid, 143) == 144
    assert more_crossings_than(grid, 144) is None
    assert more_crossings_than(fan, 10) is None
    both = fan + grid
    lines = shapely.linestrings(both)
    brute = int(np.triu(shapely.crosses(lines[:, None], lines[None, :]), 1).sum())
    assert brute > 1000 and more_crossings_than(both, 100) >= 100
    assert more_crossings_than(both, brute - 1) == brute
    # a zigzag's consecutive segments share points and overlapping boxes, and never cross
    zigzag = np.stack([np.arange(300.0), np.tile([0.0, 1.0], 150)], axis=1)
    assert more_crossings_than([zigzag], 10) is None
    assert more_crossings_than([zigzag, zigzag + [0.5, 0]], 10) >= 10
