"""Between Grease Pencil drawings as plain data and core sketches, without Blender: the
add-on's conversions import no bpy (sketchsimp_addon.drawing, sketchsimp_addon.convert)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from extension import load_extension
from helpers import ROOT, SAMPLES

load_extension()  # the repository as the extension package; registers nothing
from sketchsimp.core import (  # noqa: E402
    SAMPLES_PER_SEGMENT,
    SimplifyParams,
    SketchError,
    read_sketch,
    simplify,
)
from sketchsimp.sketchsimp_addon.convert import (  # noqa: E402
    KNOTS_PER_SEGMENT,
    drawing_from_polylines,
    drawing_plane,
    far_out,
    to_new_strokes,
    to_sketch,
)
from sketchsimp.sketchsimp_addon.drawing import DrawingData  # noqa: E402


def drawing_of(strokes: list[np.ndarray], cyclic: list[bool] | None = None,
               material: list[int] | None = None) -> DrawingData:
    """A drawing of 3D strokes with a radius growing along each, as Blender would hold it."""
    sizes = [len(s) for s in strokes]
    n = sum(sizes)
    return DrawingData(
        positions=np.concatenate(strokes).astype(np.float32),
        offsets=np.concatenate([[0], np.cumsum(sizes)]).astype(np.int32),
        radius=np.linspace(0.01, 0.02, n).astype(np.float32),
        opacity=np.full(n, 0.8, np.float32), vertex_color=None,
        material_index=np.array(material or [0] * len(strokes), np.int32),
        cyclic=np.array(cyclic or [False] * len(strokes), bool),
        selected=np.ones(len(strokes), bool), curve_type=np.ones(len(strokes), np.int8))


def front_view(name: str) -> list[np.ndarray]:
    """A sample sketch on the X-Z plane at y = 0.3, in metres."""
    return [np.stack([s.points[:, 0] * 0.01, np.full(len(s), 0.3), -s.points[:, 1] * 0.01],
                     axis=1) for s in read_sketch(SAMPLES / f"{name}.scap").strokes]


def test_the_addon_conversions_import_without_blender():
    # in a fresh interpreter: this one may have imported bpy for the add-on tests
    code = ("import sys; from extension import load_extension; load_extension(); "
            "import sketchsimp.sketchsimp_addon.convert; print('bpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT / "scripts", text=True,
                         capture_output=True, check=True)
    assert out.stdout.strip() == "False"


def test_a_front_view_drawing_is_projected_onto_its_own_plane_and_back():
    strokes = front_view("house")
    plane = drawing_plane(np.concatenate(strokes))
    assert abs(plane.axes[:, 1]).max() < 1e-9  # the plane is X-Z: no Y in either axis
    flat = plane.to_2d(strokes[0])
    np.testing.assert_allclose(plane.to_3d(flat), strokes[0], atol=1e-6)


def test_chosen_strokes_become_a_sketch_with_width_style_and_source_ids():
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], float)
    line = np.array([[0, 0, 2], [1, 0, 2.5]], float)
    data = drawing_of([line, square, line + [0, 0, 1]], cyclic=[False, True, False],
                      material=[0, 3, 1])
    sketch = to_sketch(data, [1, 2], drawing_plane(data.positions))
    loop, other = sketch.strokes
    assert (loop.source_id, loop.style, other.source_id, other.style) == (1, "3", 2, "1")
    assert len(loop.points) == 5 and np.allclose(loop.points[0], loop.points[-1])  # closed
    np.testing.assert_allclose(loop.width[:4], data.radius[2:6])
    assert loop.width[4] == loop.width[0]


def test_no_strokes_chosen_is_a_clear_error():
    data = drawing_of([np.array([[0, 0, 0], [1, 0, 0]], float)])
    with pytest.raises(SketchError, match="no strokes"):
        to_sketch(data, [], drawing_plane(data.positions))


def test_output_strokes_become_bezier_knots_on_the_plane_with_the_ink_radius():
    strokes = front_view("cup")
    data = drawing_of(strokes)
    plane = drawing_plane(data.positions)
    result = simplify(to_sketch(data, list(range(len(strokes))), plane), SimplifyParams())
    new = to_new_strokes(result.strokes, data, plane)
    assert len(new.knots) == len(result.strokes) > 0
    for s, knots, left, right, radius in zip(result.strokes, new.knots, new.handles_left,
                                             new.handles_right, new.radius):
        # each fitted cubic is written as KNOTS_PER_SEGMENT cubics of the same shape
        n_knots = ((len(s.bezier) - 1) // 3) * KNOTS_PER_SEGMENT + 1 - bool(s.closed)
        assert len(knots) == len(left) == len(right) == len(radius) == n_knots
        np.testing.assert_allclose(plane.to_2d(knots)[::KNOTS_PER_SEGMENT],
                                   s.bezier[::3][:len(knots[::KNOTS_PER_SEGMENT])], atol=1e-5)
        # knot i lies on the sampled polyline at point i * SAMPLES_PER_SEGMENT / parts, and
        # the radius is the ink's there
        at = np.arange(n_knots) * (SAMPLES_PER_SEGMENT // KNOTS_PER_SEGMENT)
        np.testing.assert_allclose(plane.to_2d(knots), s.points[at], atol=1e-5)
        np.testing.assert_allclose(radius, s.width[at], rtol=1e-6)
        assert abs(plane.to_2d(knots)).max() < 10  # on the plane, near the drawing
        assert np.all(abs((knots - plane.centre) @ np.cross(*plane.axes)) < 1e-5)
    assert new.cyclic.tolist() == [bool(s.closed) for s in result.strokes]


def test_curve_splines_read_as_a_drawing_with_grease_pencil_defaults():
    lines = [np.array([[0, 0, 0], [1, 0, 0], [2, 0, 1]], float), np.zeros((2, 3)) + 1]
    data = drawing_from_polylines(lines, [False, True])
    assert data.num_strokes == 2 and data.offsets.tolist() == [0, 3, 5]
    assert np.all(data.radius == np.float32(0.01)) and np.all(data.opacity == 1)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_strokes_along_one_axis_keep_their_length(axis):
    """Strokes lying exactly on one line (along X, Y or Z) are on a plane through it:
    along Y they used to be projected onto X-Z, each to a single point."""
    t = np.linspace(0, 1, 20)
    strokes = []
    for k in range(5):
        p = np.zeros((20, 3))
        p[:, axis] = t + 2 * k
        strokes.append(p)
    data = drawing_of(strokes)
    sketch = to_sketch(data, list(range(5)), drawing_plane(data.positions))
    for s in sketch.strokes:
        assert np.hypot(*np.ptp(s.points, axis=0)) == pytest.approx(1.0, rel=1e-6)


def test_a_negative_radius_and_an_opacity_over_one_are_not_copied_on():
    strokes = front_view("cup")
    data = drawing_of(strokes)
    data.radius[:] = -0.02
    data.opacity[:] = 3.0
    plane = drawing_plane(data.positions)
    result = simplify(to_sketch(data, list(range(len(strokes))), plane), SimplifyParams())
    new = to_new_strokes(result.strokes, data, plane)
    assert all((r >= 0).all() for r in new.radius)
    assert all(((o >= 0) & (o <= 1)).all() for o in new.opacity)


def test_a_point_at_1e30_is_broken_data_and_ordinary_ink_is_not():
    strokes = front_view("house")
    pts = np.concatenate(strokes)
    assert not far_out(pts).any()
    broken = pts.copy()
    broken[7] = [1e30, 0.3, 5.0]
    broken[20] = [-3e9, 0.3, 0.0]
    assert np.flatnonzero(far_out(broken)).tolist() == [7, 20]
    far_mark = np.concatenate([pts, pts[:2] + [40.0, 0, 0]])  # a stray mark is ink
    assert not far_out(far_mark).any()


def test_a_dense_layer_finds_its_plane_in_memory_linear_in_its_points():
    # 200,000 points on a tilted plane: the full SVD's n x n factor would be 320 GB
    import tracemalloc

    rng = np.random.default_rng(7)
    uv = rng.uniform(-1, 1, (200_000, 2))
    normal = np.array([0.2, -0.3, 1.0]) / np.linalg.norm([0.2, -0.3, 1.0])
    a = np.cross(normal, [1.0, 0, 0])
    a /= np.linalg.norm(a)
    b = np.cross(normal, a)
    pts = uv[:, :1] * a + uv[:, 1:] * b + [5.0, 1.0, -2.0]
    tracemalloc.start()
    try:
        plane = drawing_plane(pts)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 60 * pts.nbytes  # a few copies of the points, never n x n
    fitted = np.cross(*plane.axes)
    assert abs(abs(fitted @ normal) - 1) < 1e-9  # the plane is the points' own
