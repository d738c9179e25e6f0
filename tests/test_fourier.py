"""Fourier descriptors: invariances and the paper's Fig. 12 bending test."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import circle

from core.merge.fourier import (
    curve_descriptors,
    fd_distance,
    fourier_descriptor,
    fourier_descriptors,
    resample_ring,
    slender_ring,
)


def star(n_points: int = 5, samples: int = 300) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, samples, endpoint=False)
    r = 1 + 0.3 * np.cos(n_points * t)
    return np.stack([r * np.cos(t), r * np.sin(t)], axis=1)


def rotate(p, angle):
    c, s = np.cos(angle), np.sin(angle)
    return p @ np.array([[c, s], [-s, c]])


def test_descriptor_shape_and_circle():
    fd = fourier_descriptor(circle(0, 0, 1, 400)[:-1])
    assert fd.shape == (128,)
    assert np.abs(fd).max() < 1e-3  # a circle's centroid distance is constant


def test_invariant_to_translation_rotation_scale_and_start_point():
    ring = star()
    base = fourier_descriptor(ring)
    moved = rotate(ring, 0.7) * 13.0 + np.array([100.0, -5.0])
    shifted = np.roll(ring, 77, axis=0)
    for other in (moved, shifted, ring[::-1]):
        assert fd_distance(base, fourier_descriptor(other)) < 2e-3
    # and it does tell shapes apart
    assert fd_distance(base, fourier_descriptor(star(3))) > 0.1


def test_batch_equals_one_at_a_time():
    rings = [star(3), star(5, 50), circle(0, 0, 1, 20)[:-1]]
    batch = fourier_descriptors(rings, 64)
    for ring, fd in zip(rings, batch):
        np.testing.assert_allclose(fd, fourier_descriptor(ring, 64), atol=1e-12)


def test_resampling_is_even_by_arc_length():
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    pts = resample_ring(sq, 8)
    np.testing.assert_allclose(pts, [[0, 0], [.5, 0], [1, 0], [1, .5], [1, 1], [.5, 1],
                                     [0, 1], [0, .5]])
    np.testing.assert_allclose(resample_ring(sq * 2, 8), pts * 2)


def test_curve_descriptor_is_the_descriptor_of_its_slender_ring():
    t = np.linspace(0, 2, 57)
    curve = np.stack([t, np.sin(t) * 0.4], axis=1)
    direct = curve_descriptors([curve])[0]
    np.testing.assert_allclose(direct, fourier_descriptor(slender_ring(curve)), atol=1e-9)


def test_slender_ring():
    c = np.array([[0, 0], [1, 0], [2, 0], [3, 0]], float)
    np.testing.assert_array_equal(slender_ring(c), [[0, 0], [1, 0], [2, 0], [3, 0], [2, 0],
                                                    [1, 0]])


def test_fig12_more_bend_means_larger_distance_from_the_straight_line():
    """Eight curves of equal length bent ever more: distances to the straight one increase."""
    curves = []
    for bend in np.radians([0, 20, 40, 60, 80, 100, 120, 140]):
        s = np.linspace(-0.5, 0.5, 100)
        if bend == 0:
            curves.append(np.stack([s, 0 * s], axis=1))
        else:
            r = 1 / bend  # an arc of length 1 that turns through ``bend``
            curves.append(np.stack([r * np.sin(s / r), r * (1 - np.cos(s / r))], axis=1))
    fds = curve_descriptors(curves)
    d = fd_distance(fds[0], fds[1:])
    assert np.all(np.diff(d) > 0), d
    assert d[0] > 0


@pytest.mark.parametrize("n", [8, 64, 256, 1024])
def test_sample_count_sets_the_length(n):
    assert curve_descriptors([np.array([[0, 0], [1, 1], [2, 0]], float)], n).shape == (1, n // 2)
