"""Schneider Bezier fitting: error bound, corners, no blow-ups."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from core.arrays.polylines import resample_polyline
from core.curves.bezier import (
    corner_indices,
    fit_bezier,
    fit_beziers,
    sample_bezier,
    smooth_between_corners,
)


def distance_to(points, polyline):
    return shapely.distance(shapely.points(points), shapely.LineString(polyline))


def test_arc_within_the_error_bound_and_few_segments():
    t = np.linspace(0, np.pi, 200)
    arc = np.stack([np.cos(t), np.sin(t)], axis=1)
    ctrl = fit_bezier(arc, 1e-3)
    assert (len(ctrl) - 1) % 3 == 0 and len(ctrl) <= 3 * 4 + 1
    assert np.abs(np.hypot(*sample_bezier(ctrl, 32).T) - 1).max() < 2e-3
    np.testing.assert_allclose(ctrl[[0, -1]], arc[[0, -1]])


def test_square_keeps_its_four_corners():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], float)
    ctrl = fit_bezier(resample_polyline(square, 0.01), 0.002, closed=True)
    knots = ctrl[::3]
    for corner in square[:4]:
        assert np.hypot(*(knots - corner).T).min() < 1e-9
    assert len(knots) == 5  # one cubic per side: straight sides need no more


def test_corner_detection_sees_sharp_turns_only():
    t = np.linspace(0, 1, 50)
    v = np.concatenate([np.stack([t, t], 1), np.stack([1 + t, 1 - t], 1)[1:]])
    assert corner_indices(v, 50, 0.05) == [49]
    gentle = np.stack([t, 0.1 * np.sin(3 * t)], axis=1)
    assert corner_indices(gentle, 50, 0.05) == []


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(-1, 1), st.floats(-1, 1)), min_size=2, max_size=12),
       st.sampled_from([1e-3, 1e-2, 5e-2]))
def test_fits_never_blow_up(raw, tol):
    pts = np.array(raw, dtype=float)
    keep = np.concatenate([[True], np.hypot(*np.diff(pts, axis=0).T) > 1e-6])
    pts = pts[keep]
    if len(pts) < 2:
        return
    ctrl = fit_bezier(pts, tol)
    assert np.isfinite(ctrl).all()
    # the data points are fitted within the bound ...
    assert distance_to(pts, sample_bezier(ctrl, 64)).max() <= tol * 1.01 + 1e-9
    # ... and the curve does not wander off between them
    length = np.hypot(*np.diff(pts, axis=0).T).sum()
    assert distance_to(sample_bezier(ctrl, 64), pts).max() <= 0.5 * length + 1e-9


def test_a_closed_loop_shorter_than_the_spacing_stays_a_loop():
    """Regression (a real design sketch crashed): resampling a short closed stroke gave two
    equal points, and the fit refused them."""
    t = np.linspace(0, 2 * np.pi, 9)
    loop = np.stack([0.001 * np.cos(t), 0.001 * np.sin(t)], axis=1)
    loop[-1] = loop[0]  # closed exactly, as joined strokes are
    pts = resample_polyline(loop, 0.01)  # longer than the loop itself
    assert len(pts) >= 4 and np.hypot(*np.diff(pts, axis=0).T).min() > 0
    ctrl = fit_bezier(pts, 1e-4, closed=True)
    np.testing.assert_allclose(ctrl[0], ctrl[-1], atol=1e-12)


def test_polylines_fitted_together_are_each_fitted_alone():
    """The output stage fits every new stroke in one batch (a level of splitting at a time
    for all): each fit is, to the bit, its fit alone, so replays equal fresh runs."""
    rng = np.random.default_rng(5)
    polylines, closed = [], []
    for k in range(30):
        n = int(rng.integers(2, 80))
        t = np.linspace(0, rng.uniform(1, 6), n)
        wiggle = rng.uniform(0, 0.3) * np.sin(rng.uniform(1, 9) * t)
        pts = np.stack([t, wiggle + rng.normal(0, 0.01, n)], axis=1)
        if k % 7 == 0 and n > 4:  # a loop
            pts = np.concatenate([pts, pts[:1]])
        polylines.append(pts)
        closed.append(k % 7 == 0 and n > 4)
    polylines.append(np.array([[0, 0], [1, 1]], float))  # two points: no fit to make
    closed.append(False)
    together = fit_beziers(polylines, 0.01, 50.0, closed)
    alone = [fit_bezier(p, 0.01, 50.0, closed=c) for p, c in zip(polylines, closed)]
    assert sum(len(c) > 4 for c in alone) > 10  # most are split into several cubics
    for a, b in zip(together, alone):
        assert a.tobytes() == b.tobytes()


def test_smoothing_takes_the_step_out_of_a_line_and_keeps_its_corners_and_ends():
    """A line passing from one stroke of a bundle to the next (a step of 0.4, sampled every
    0.25, as the output stage samples at a quarter of d_eps = 1) comes out without the
    step; an L keeps its corner point and both ends exactly."""
    x = np.arange(0, 10.01, 0.25)
    step = np.column_stack([x, np.where(x < 5, 0.0, 0.4)])
    smooth = smooth_between_corners(step, 2.0, corner_indices(step, 50.0, 1.0))
    assert np.abs(np.diff(smooth[:, 1])).max() < 0.1  # spread over 5 samples: was one jump of 0.4
    assert np.abs(np.diff(step[:, 1])).max() == pytest.approx(0.4)
    np.testing.assert_array_equal(smooth[[0, -1]], step[[0, -1]])
    t = np.arange(0, 5.01, 0.25)
    ell = np.vstack([np.column_stack([t, 0 * t]), np.column_stack([5 + 0 * t[1:], t[1:]])])
    corners = corner_indices(ell, 50.0, 1.0)
    assert corners == [20]
    kept = smooth_between_corners(ell, 2.0, corners)
    np.testing.assert_allclose(kept, ell, atol=1e-12)  # straight pieces stay as they are
