"""Curve-curve pairing and merging, one pair at a time and many at once."""

from __future__ import annotations

import numpy as np
import pytest

from core.arrays.polylines import arc_lengths, resample_polyline
from core.merge.curve_merge import SampledCurve, pair_and_merge, pair_and_merge_many, sample_spacing

D_EPS = 0.012
ANGLE = 30.0


def _curve(points) -> SampledCurve:
    return SampledCurve.many([np.asarray(points, dtype=float)], sample_spacing(D_EPS))[0]


def _line(x0, y0, x1, y1, n=20, wobble=0.0, seed=0) -> SampledCurve:
    t = np.linspace(0, 1, n)[:, None]
    pts = (1 - t) * [x0, y0] + t * [x1, y1]
    pts[1:-1] += np.random.default_rng(seed).normal(0, wobble, (n - 2, 2))
    return _curve(pts)


def test_side_by_side_strokes_merge_between_them():
    a = _line(0, 0, 0.3, 0)
    b = _line(0.02, 0.006, 0.28, 0.006)
    how, merged = pair_and_merge(a, 1.0, b, 1.0, D_EPS, ANGLE)
    assert how == "side"
    inside = (merged[:, 0] > 0.05) & (merged[:, 0] < 0.25)
    assert np.allclose(merged[inside, 1], 0.003, atol=1e-9)  # the middle, equal weights
    assert merged[:, 0].min() == pytest.approx(0) and merged[:, 0].max() == pytest.approx(0.3)


def test_weights_pull_the_merged_curve_to_the_heavier():
    a = _line(0, 0, 0.3, 0)
    b = _line(0, 0.006, 0.3, 0.006)
    _, merged = pair_and_merge(a, 3.0, b, 1.0, D_EPS, ANGLE)
    assert np.allclose(merged[5:-5, 1], 0.0015, atol=1e-9)


def test_crossing_lines_and_far_lines_do_not_pair():
    a = _line(0, 0, 0.3, 0)
    assert pair_and_merge(a, 1.0, _line(0.15, -0.1, 0.15, 0.1), 1.0, D_EPS, ANGLE) == (None, None)
    assert pair_and_merge(a, 1.0, _line(0, 0.05, 0.3, 0.05), 1.0, D_EPS, ANGLE) == (None, None)


def test_a_stroke_carried_on_pairs_end_to_end_unless_end_to_end_is_left_out():
    a = _line(0, 0, 0.2, 0)
    b = _line(0.205, 0.001, 0.4, 0.002)
    how, merged = pair_and_merge(a, 1.0, b, 1.0, D_EPS, ANGLE)
    assert how == "end"
    assert merged[:, 0].min() == pytest.approx(0) and merged[:, 0].max() == pytest.approx(0.4)
    assert pair_and_merge(a, 1.0, b, 1.0, D_EPS, ANGLE, end_to_end=False) == (None, None)


def test_a_stroke_drawn_on_over_the_end_of_the_last_pairs_as_an_overlap():
    """The second stroke starts beside the first, 0.05 before its end (a fifth of the
    shorter: neither side by side nor end to end), and carries on: one curve, the middle
    of the two over the overlap."""
    a = _line(0, 0, 0.3, 0)
    b = _line(0.25, 0.004, 0.5, 0.004)
    how, merged = pair_and_merge(a, 1.0, b, 1.0, D_EPS, ANGLE)
    assert how == "overlap"
    assert merged[:, 0].min() == pytest.approx(0) and merged[:, 0].max() == pytest.approx(0.5)
    middle = (merged[:, 0] > 0.27) & (merged[:, 0] < 0.28)
    assert np.allclose(merged[middle, 1], 0.002, atol=2e-4)
    # the bi-edge pass, which leaves end-to-end joins to the stroke graph, merges it too
    assert pair_and_merge(a, 1.0, b, 1.0, D_EPS, ANGLE, end_to_end=False)[0] == "overlap"


def test_overlaps_that_are_crossings_branches_or_touches_do_not_pair():
    a = _line(0, 0, 0.3, 0)
    touch = _line(0.295, 0.004, 0.5, 0.004)  # beside it for less than d_eps: not an overlap
    assert pair_and_merge(a, 1.0, touch, 1.0, D_EPS, ANGLE)[0] != "overlap"
    # runs beside it, then leaves at 45 degrees before its end: a branch
    branch = _curve([[0.1, 0.004], [0.2, 0.004], [0.35, 0.154]])
    assert pair_and_merge(a, 1.0, branch, 1.0, D_EPS, ANGLE) == (None, None)
    # beside its end, then turning back over it: a hook, not a stroke carried on
    hook = _curve([[0.25, 0.004], [0.4, 0.004], [0.4, 0.1], [0.2, 0.1]])
    assert pair_and_merge(a, 1.0, hook, 1.0, D_EPS, ANGLE) == (None, None)


def _assorted_curves() -> list[SampledCurve]:
    """Strokes of a rough bundle, their reversals, crossings, continuations and crumbs."""
    curves = [_line(0, 0.004 * k, 0.3 + 0.01 * k, 0.004 * k, wobble=0.001, seed=k)
              for k in range(4)]
    curves += [_curve(c.points[::-1]) for c in curves[:2]]
    curves += [_line(0.1, -0.1, 0.12, 0.1), _line(0.305, 0.001, 0.5, 0.01, seed=9),
               _line(0.15, 0.002, 0.152, 0.003, n=2)]
    arc = np.linspace(0, np.pi / 2, 40)
    curves += [_curve(np.c_[0.3 * np.cos(arc), 0.3 * np.sin(arc)] + [0, -0.3 + 0.005 * k])
               for k in range(2)]
    return curves


@pytest.mark.parametrize("end_to_end", [True, False])
def test_many_pairs_at_once_are_each_pair_on_its_own(end_to_end):
    curves = _assorted_curves()
    pairs = [(curves[i], 1.0 + i % 3, curves[j], 1.0 + j % 2)
             for i in range(len(curves)) for j in range(i + 1, len(curves))]
    together = pair_and_merge_many(pairs, D_EPS, ANGLE, end_to_end)
    alone = [pair_and_merge(*p, D_EPS, ANGLE, end_to_end) for p in pairs]
    kinds = {how for how, _ in alone}
    assert kinds == ({None, "side", "overlap", "end"} if end_to_end else {None, "side", "overlap"})
    for (how, merged), (how1, merged1) in zip(together, alone):
        assert how == how1
        if how is not None:
            np.testing.assert_array_equal(merged, merged1)  # to the bit


def test_curves_sampled_together_are_each_sampled_alone():
    rng = np.random.default_rng(3)
    arc = np.linspace(0, 2 * np.pi, 30)
    polylines = [rng.random((k, 2)) * 0.2 for k in (2, 3, 17)]
    polylines += [np.c_[np.cos(arc), np.sin(arc)] * 0.01, np.array([[0.1, 0.1], [0.1, 0.1]])]
    spacing = sample_spacing(D_EPS)
    together = SampledCurve.many(polylines, spacing)
    for polyline, curve in zip(polylines, together):
        alone = SampledCurve.many([polyline], spacing)[0]
        np.testing.assert_array_equal(curve.points, resample_polyline(polyline, spacing))
        np.testing.assert_array_equal(curve.s, arc_lengths(curve.points))
        for a, b in ((curve.points, alone.points), (curve.tangents, alone.tangents)):
            np.testing.assert_array_equal(a, b)
        assert np.allclose(np.hypot(*curve.tangents.T), 1) or curve.length == 0
    assert len(together[3].points) >= 4  # a loop stays a loop
    line = SampledCurve.many([np.array([[0.0, 0.0], [0.3, 0.4]])], spacing)[0]
    np.testing.assert_allclose(line.tangents, np.tile([0.6, 0.8], (len(line.points), 1)))
