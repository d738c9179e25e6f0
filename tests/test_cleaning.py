"""Cleaning and normalisation."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import SAMPLES

from core import Sketch, SketchError, Stroke, build_base_complex, clean_sketch, read_sketch
from core.io.cleaning import Normalisation, normalised_strokes


def test_cleaning_removes_and_counts_what_cannot_be_drawn():
    nan, inf = np.nan, np.inf
    sketch = Sketch([
        Stroke([[0, 0], [nan, 1], [1, 1], [1, 1], [2, 2]], width=[1, 2, 3, 4, 5]),
        Stroke([[5, 5], [5, 5], [5, 5]]),  # one distinct point
        Stroke([[inf, 0], [3, 3]]),  # one finite point
        Stroke([[0, 0], [0, 1], [0, 0]]),  # back and forth is fine
    ])
    cleaned, report = clean_sketch(sketch)
    assert report.as_dict() == {"strokes_in": 4, "strokes_out": 2, "nonfinite_points": 2,
                                "duplicate_points": 3, "degenerate_strokes": 2}
    np.testing.assert_array_equal(cleaned.strokes[0].points, [[0, 0], [1, 1], [2, 2]])
    np.testing.assert_array_equal(cleaned.strokes[0].width, [1, 3, 5])
    assert len(cleaned.strokes[1]) == 3
    # the input is left as it was
    assert len(sketch.strokes[0]) == 5


@pytest.mark.parametrize("sketch, message", [
    (Sketch([]), "no strokes"),
    (Sketch([Stroke([[1, 1], [1, 1]])]), "two distinct"),
    ("not a sketch", "expected a Sketch"),
])
def test_unusable_sketches_raise(sketch, message):
    with pytest.raises(SketchError, match=message):
        clean_sketch(sketch)


def test_normalisation_maps_to_unit_diagonal_and_back():
    sketch = Sketch([Stroke([[10, 20], [40, 60]])])
    strokes, norm = normalised_strokes(sketch)
    assert norm.scale == pytest.approx(50)
    np.testing.assert_allclose(strokes[0], [[0, 0], [0.6, 0.8]])
    np.testing.assert_allclose(norm.from_unit(strokes[0]), sketch.strokes[0].points)
    with pytest.raises(SketchError, match="zero extent"):
        Normalisation.of(Sketch([Stroke([[1, 1], [1, 1]])]))
    for extent in (2e-308, 1e200):  # found by the random-sketch test: subnormal extents
        with pytest.raises(SketchError, match="cannot be measured"):
            Normalisation.of(Sketch([Stroke([[0, 0], [0, extent]])]))


@pytest.mark.parametrize("scale", [1e9, 1e-9, 1.0])
def test_huge_and_tiny_sketches_give_the_same_complex(scale):
    sketch, _ = clean_sketch(read_sketch(SAMPLES / "house.scap"))
    scaled = Sketch([Stroke(s.points * scale + 7 * scale) for s in sketch.strokes])
    base = build_base_complex(normalised_strokes(sketch)[0])
    other = build_base_complex(normalised_strokes(scaled)[0])
    assert (other.num_nodes, other.num_curves, other.num_patches) == (
        base.num_nodes, base.num_curves, base.num_patches)
    np.testing.assert_allclose(other.nodes, base.nodes, atol=2e-6)
