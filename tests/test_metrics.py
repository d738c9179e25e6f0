"""The evaluation measures, on drawings whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest
from metrics import (
    chamfer,
    changed,
    coverage,
    doubled,
    doubled_on_reference,
    fidelity,
    moved,
    precision_recall_f,
    too_wide,
)


def drawing():
    t = np.linspace(0, 2 * np.pi, 200)
    return [np.stack([100 + 50 * np.cos(t), 100 + 50 * np.sin(t)], axis=1),
            np.array([[0.0, 0.0], [200.0, 0.0]]), np.array([[0.0, 20.0], [0.0, 180.0]])]


def test_identical_drawings_score_perfectly():
    d = drawing()
    assert precision_recall_f(d, d, tol=1.0) == (1.0, 1.0, 1.0)
    assert chamfer(d, d) == pytest.approx(0.0, abs=1e-9)
    assert coverage(d, d, tol=0.5) == 1.0
    assert fidelity(d, d) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("k", [1.0, 3.0])
def test_a_straight_drawing_shifted_by_k_has_chamfer_k(k):
    lines = [np.array([[0.0, 0.0], [300.0, 0.0]]), np.array([[0.0, 50.0], [300.0, 50.0]])]
    moved = [np.array([[0.0, k], [300.0, k]]), np.array([[0.0, 50.0 + k], [300.0, 50.0 + k]])]
    assert chamfer(lines, moved) == pytest.approx(k, rel=1e-6)
    assert fidelity(moved, lines) == pytest.approx(k, rel=1e-6)
    p, r, f = precision_recall_f(moved, lines, tol=k / 2)
    assert (p, r, f) == (0.0, 0.0, 0.0)
    assert precision_recall_f(moved, lines, tol=k * 1.01) == (1.0, 1.0, 1.0)


def test_empty_output_covers_nothing():
    d = drawing()
    assert coverage(d, [], tol=10.0) == 0.0
    assert precision_recall_f([], d, tol=10.0) == (0.0, 0.0, 0.0)


def test_half_the_ink_dropped_is_half_covered():
    full = [np.array([[0.0, 0.0], [100.0, 0.0]])]
    half = [np.array([[0.0, 0.0], [50.0, 0.0]])]
    assert coverage(full, half, tol=0.1, spacing=0.5) == pytest.approx(0.5, abs=0.01)
    p, r, _ = precision_recall_f(half, full, tol=0.1, spacing=0.5)
    assert p == 1.0 and r == pytest.approx(0.5, abs=0.01)


def line(y: float, x0: float = 0.0, x1: float = 400.0) -> np.ndarray:
    return np.array([[x0, y], [x1, y]])


def test_a_line_drawn_twice_over_one_intended_curve_is_doubled():
    ink = [line(0.0), line(3.0)]  # one intended curve, two passes
    assert doubled([line(0.0), line(3.0)], ink, [7, 7], diagonal=500.0) == 1.0
    assert doubled([line(1.5)], ink, [7, 7], diagonal=500.0) == 0.0  # merged mid-bundle


def test_two_close_lines_of_different_curves_are_not_doubled():
    ink = [line(0.0), line(3.0)]
    assert doubled([line(0.0), line(3.0)], ink, [1, 2], diagonal=500.0) == 0.0


def test_crossing_strokes_and_end_to_end_pieces_are_not_doubled():
    ink = [line(0.0), np.array([[200.0, -200.0], [200.0, 200.0]])]
    assert doubled(ink, ink, [1, 1], diagonal=500.0) == 0.0  # perpendicular
    # pieces end to end: their last 3% are left out, so at most a sample at the limit counts
    pieces = [line(0.0, 0, 200), line(0.0, 200, 400)]
    assert doubled(pieces, [line(0.0)], [1], diagonal=500.0) < 0.02


def test_half_a_line_doubled_counts_half():
    ink = [line(0.0), line(3.0, 0.0, 200.0)]
    share = doubled([line(0.0), line(3.0, 0.0, 200.0)], ink, [1, 1], diagonal=500.0)
    # the long line's left half and all of the short one's inside part, over both lengths
    assert 0.55 < share < 0.75


def test_a_bundle_wider_than_twice_the_ink_kept_tolerance_is_too_wide_for_one_line():
    # 4% of a 500 diagonal is 20: passes 0, 7 and 14 apart keep within 2% of a line at 7
    narrow = [line(0.0), line(7.0), line(14.0)]
    assert too_wide(narrow, [1, 1, 1], diagonal=500.0) == 0.0
    wide = narrow + [line(21.0)]
    assert too_wide(wide, [1, 1, 1, 1], diagonal=500.0) == 1.0
    # ... and no line does keep it all, where two lines, each a side, keep it
    assert coverage(wide, [line(10.5)], 0.02 * 500.0) < 1.0
    assert coverage(wide, [line(3.5), line(17.5)], 0.02 * 500.0) == 1.0


def test_two_curves_or_a_wide_empty_gap_are_not_one_wide_bundle():
    # the same four passes as two intended curves, each narrow
    four = [line(0.0), line(7.0), line(14.0), line(21.0)]
    assert too_wide(four, [1, 1, 2, 2], diagonal=500.0) == 0.0
    # one curve drawn twice 30 apart, nothing between: each pass can have its own line
    assert too_wide([line(0.0), line(30.0)], [1, 1], diagonal=500.0) == 0.0
    # passes across the line do not widen it
    across = [line(0.0), np.array([[200.0, -100.0], [200.0, 100.0]])]
    assert too_wide(across, [1, 1], diagonal=500.0) == 0.0


def test_changed_is_the_share_of_either_drawing_away_from_the_other():
    assert changed([line(0.0)], [line(0.0)], tol=1.0, spacing=1.0) == 0.0
    assert changed([line(0.0)], [line(0.0), line(100.0)], tol=1.0,
                   spacing=1.0) == pytest.approx(0.5, abs=0.01)


def test_lines_through_a_small_angle_crossing_a_little_off_count_as_doubled_unless_cut_there():
    """Why doubled_on_reference has a floor (``metrics.moved``): two straight lines crossing
    at 6 degrees, drawn 0.1% of the diagonal off, are doubled around the crossing; cut at
    the crossing, that stretch lies within their ends, and nothing is."""
    t = np.linspace(0, 400, 401)[:, None]
    cross = [np.hstack([t, 0 * t]), np.hstack([t, 0.1 * (t - 200)])]
    off = moved(cross, 0.5)
    assert doubled_on_reference(cross, cross, 500.0) == 0.0
    assert doubled_on_reference(off, cross, 500.0) > 0.01
    cut = [part for line in off for part in (line[:201], line[200:])]
    assert doubled_on_reference(cut, cross, 500.0) == 0.0


def test_the_scorers_examples_hold():
    """The examples in metrics.py's docstrings (scripts/, outside core's doctest check)."""
    import doctest

    import metrics

    result = doctest.testmod(metrics, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 10 and result.failed == 0


def test_the_synthetic_drawings_examples_hold():
    """The examples in synthetic_passes.py's docstrings (the rough passes, Chaikin)."""
    import doctest

    import synthetic_passes

    result = doctest.testmod(synthetic_passes, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 3 and result.failed == 0


@pytest.mark.parametrize("kind", ["handwriting", "icons", "kanji"])
def test_a_hershey_drawing_is_the_same_every_time_and_lies_on_its_canvas(kind):
    pytest.importorskip("HersheyFonts")
    from synthetic_passes import hershey_drawing

    curves, width, height = hershey_drawing(kind, 3)
    again, *_ = hershey_drawing(kind, 3)
    other, *_ = hershey_drawing(kind, 4)
    ink = np.vstack(curves)
    assert len(curves) >= 4 and all(np.array_equal(a, b) for a, b in zip(curves, again))
    assert not all(len(a) == len(b) and np.array_equal(a, b) for a, b in zip(curves, other))
    assert ink.min() > 0 and (ink.max(axis=0) < [width, height]).all()


def test_a_kanji_drawing_draws_each_wide_stroke_once():
    """The font draws a wide stroke as two lines about a unit apart; the kanji kind keeps
    one (a hand draws it once), so no curve lies along another."""
    pytest.importorskip("HersheyFonts")
    import shapely
    from synthetic_passes import DOUBLE_REACH, hershey_drawing

    for index in range(4):
        curves, *_ = hershey_drawing("kanji", index)
        lines = [shapely.LineString(c) for c in curves]
        for k, line in enumerate(lines):
            points = shapely.points(shapely.segmentize(line, 0.25).coords)
            for o, other in enumerate(lines):
                if o != k:
                    assert (shapely.distance(points, other) <= DOUBLE_REACH).mean() < 0.8


def test_join_refusals_names_the_joint_fit_for_passes_it_moves_and_fewer_under_a_wider_reach():
    """scripts/join_refusals.py: on a synthetic handwriting drawing, some passes of one
    curve are left apart by the joint fit's move test (a lone pass beside its bundle);
    with ``join_reach`` four times wider fewer are, and every reason is a named one."""
    pytest.importorskip("HersheyFonts")
    from join_refusals import REASONS, one

    def moved(tuning: dict) -> int:
        _, rows = one(("handwriting/0", tuning))
        assert rows and all(r["reason"] in REASONS for r in rows)
        return sum(r["true"] and r["reason"] == "joint fit" for r in rows)

    assert moved({}) > moved({"join_reach": 2.0})


def test_join_refusals_finds_passes_of_one_line_drawn_back_and_forth_on_a_real_sketch():
    """scripts/join_refusals.py's drawing order, on a real labelled product sketch drawn in
    order: some pair of one label left apart was drawn interleaved, and the pairs of two
    labels lie farther apart in the order than those of one (median order gap)."""
    from join_refusals import DATA, one, sources

    files = [f for f in sources("lift3d", DATA) if "designer2" in f or "student" in f]
    if not files:
        pytest.skip(f"no lift3d sketches under {DATA}")
    _, rows = one((files[0], {}))
    true = [r for r in rows if r["true"]]
    false = [r for r in rows if not r["true"]]
    assert true and false
    assert any(r["interleaved"] for r in true)
    assert np.median([r["order_gap"] for r in false]) > np.median([r["order_gap"]
                                                                   for r in true])
