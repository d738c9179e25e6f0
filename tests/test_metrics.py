"""The evaluation measures, on drawings whose answer is known."""

from __future__ import annotations

import numpy as np
import pytest
from metrics import chamfer, coverage, fidelity, precision_recall_f


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
