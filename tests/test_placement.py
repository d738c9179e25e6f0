"""Step 9, placement: output lines move onto the middle of their ink, junctions held."""

from __future__ import annotations

import numpy as np
import shapely

from core.arrays.polylines import resample_polyline
from core.curves.attributes import NearestInk
from core.output.placement import centred_on_ink
from core.sketch import Stroke

REACH, SPACING = 0.04, 0.005


def _ink(passes: list[np.ndarray]) -> NearestInk:
    return NearestInk([Stroke(p) for p in passes], passes)


def _line(*points) -> np.ndarray:
    return resample_polyline(np.array(points, dtype=float), SPACING)


def _horizontal(y: float, x0: float = 0.0, x1: float = 1.0) -> np.ndarray:
    x = np.linspace(x0, x1, 201)
    return np.column_stack([x, np.full_like(x, y)])


def test_a_line_off_the_middle_of_a_bundle_moves_towards_it():
    ink = _ink([_horizontal(y) for y in (0.0, 0.02, 0.04)])
    line = _line((0, 0.012), (1, 0.012))
    moved, = centred_on_ink([line], [False], ink, REACH, SPACING)
    before, after = abs(line[:, 1] - 0.02), abs(moved[:, 1] - 0.02)
    assert (after < 0.7 * before).all()
    assert np.allclose(moved[:, 0], line[:, 0])  # across the line, not along it


def test_ink_across_a_line_does_not_move_it():
    ink = _ink([np.array([[0.5, -0.5], [0.5, 0.5]]), np.array([[0.3, -0.5], [0.32, 0.5]])])
    line = _line((0, 0.0), (1, 0.0))
    moved, = centred_on_ink([line], [False], ink, REACH, SPACING)
    assert np.array_equal(moved, line)


def test_ink_nearer_another_line_is_that_lines():
    # two distinct lines 0.03 apart, each drawn once where it lies: both in reach of the
    # other's ink, neither pulled towards it
    ink = _ink([_horizontal(0.0), _horizontal(0.03)])
    lines = [_line((0, 0.0), (1, 0.0)), _line((0, 0.03), (1, 0.03))]
    moved = centred_on_ink(lines, [False, False], ink, REACH, SPACING)
    for a, b in zip(lines, moved):
        assert np.abs(a - b).max() < 1e-12


def test_a_line_ending_on_another_stays_on_it():
    # a T: the bar's ink lies 0.01 below it, so the bar moves down, away from the junction
    ink = _ink([_horizontal(-0.01), np.array([[0.5, 0.0], [0.5, 0.5]])])
    bar, stem = _line((0, 0.0), (1, 0.0)), _line((0.5, 0.0), (0.5, 0.5))
    bar_moved, stem_moved = centred_on_ink([bar, stem], [False, False], ink, REACH, SPACING)
    assert bar_moved[:, 1].min() < -0.004  # it moved where no line meets it
    joint = shapely.distance(shapely.LineString(bar_moved), shapely.Point(stem_moved[0]))
    assert joint < 1e-12


def test_a_line_ending_on_itself_stays_closed():
    # a "6": a loop whose end comes back onto the stroke's own start, ink offset inside it
    t = np.linspace(0, 2 * np.pi, 400)
    loop = np.column_stack([0.2 * np.cos(t), 0.2 * np.sin(t) + 0.2])
    six = resample_polyline(np.vstack([[[0.2, 0.6]], loop[::-1][:-1]]), SPACING)
    ink = _ink([0.97 * (loop - [0, 0.2]) + [0, 0.2], np.array([[0.2, 0.6], [0.2, 0.2]])])
    start = shapely.LineString(six[:len(six) // 3])
    assert shapely.distance(start, shapely.Point(six[-1])) < SPACING / 2  # it meets itself
    moved, = centred_on_ink([six], [False], ink, REACH, SPACING)
    assert np.abs(moved - six).max() > 0.002  # the loop moved
    before = shapely.distance(start, shapely.Point(six[-1]))
    after = shapely.distance(shapely.LineString(moved[:len(six) // 3]), shapely.Point(moved[-1]))
    assert after <= before + 1e-12
