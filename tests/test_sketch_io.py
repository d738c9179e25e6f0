"""Sketch model, .scap and SVG reading and writing."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from helpers import ROOT, SAMPLES

from core import Sketch, SketchError, Stroke, read_sketch, write_sketch
from core.io.scap import format_scap, parse_scap
from core.io.svg import parse_svg

SCAP = """#400\t300
@1.5
{
\t#0\t7
\t10 20 0
\t30 40 0.5
}
{
\t#1\t7
\t@2
\t50 60 0
\t70 80 0
\t90 100 0
}
#0 [0, 1) --> #5
"""


def test_stroke_validates_shape_and_dtype():
    with pytest.raises(SketchError, match="shape"):
        Stroke(np.zeros((4, 3)))
    with pytest.raises(SketchError, match="real numbers"):
        Stroke(np.array([["a", "b"]]))
    with pytest.raises(SketchError):
        Stroke([[0, 0], [1]])
    with pytest.raises(SketchError, match="one value per point"):
        Stroke(np.zeros((3, 2)), width=np.ones(2))
    s = Stroke(np.array([[0, 0], [1, 1]], dtype=np.int32), width=2.0)
    assert s.points.dtype == np.float64 and s.width.tolist() == [2.0, 2.0]
    assert issubclass(SketchError, ValueError)


def test_scap_parse_keeps_clusters_thickness_and_skips_cut_records():
    sk = parse_scap(SCAP)
    assert (sk.width, sk.height) == (400, 300)
    assert [len(s) for s in sk.strokes] == [2, 3]
    assert [s.cluster for s in sk.strokes] == [7, 7]
    assert [s.source_id for s in sk.strokes] == [0, 1]
    assert sk.strokes[0].width.tolist() == [1.5, 1.5]
    assert sk.strokes[1].width.tolist() == [2.0] * 3
    assert sk.strokes[0].pressure.tolist() == [0, 0.5]
    np.testing.assert_array_equal(sk.strokes[1].points[2], [90, 100])


def test_scap_round_trip():
    sk = parse_scap(SCAP)
    again = parse_scap(format_scap(sk))
    assert [s.cluster for s in again.strokes] == [7, 7]
    for a, b in zip(sk.strokes, again.strokes):
        np.testing.assert_allclose(a.points, b.points)


@pytest.mark.parametrize("text, message", [
    ("{\n1 2 0\n", "not closed"),
    ("{\n1 x 0\n}\n", "expected numbers"),
    ("hello\n", "unexpected text"),
    ("#10 10\n", "no strokes"),
    ("{\n1 2 0\n3 4\n}\n", "unequal"),
])
def test_scap_errors_are_clear(text, message):
    with pytest.raises(SketchError, match=message):
        parse_scap(text)


SVG_ALL_COMMANDS = b"""<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200">
  <g transform="translate(100 0)"><g transform="scale(2)">
    <path id="abs" d="M0 0 L10 0 H20 V10 C20 20 30 20 30 10 S40 0 40 10 Q50 20 60 10 T80 10
                      A10 10 0 0 1 100 10 Z" stroke="#ff0000" stroke-width="0.5"/>
    <path id="rel" d="m0 50 l10 0 h10 v10 c0 10 10 10 10 0 s10 -10 10 0 q10 10 20 0 t20 0
                      a10 10 0 0 1 20 0 z"/>
  </g></g>
  <polyline points="0,0 10,10 20,0"/><polygon points="0,100 10,110 20,100"/>
  <line x1="0" y1="150" x2="50" y2="150"/>
</svg>"""


def test_svg_reads_every_command_with_nested_transforms():
    sk = parse_svg(SVG_ALL_COMMANDS, tolerance=0.01)
    assert len(sk.strokes) == 5
    absolute, relative = sk.strokes[0], sk.strokes[1]
    # M0 0 under translate(100) scale(2) -> (100, 0); the arc ends at x = 100 + 2 * 100
    np.testing.assert_allclose(absolute.points[0], [100, 0])
    assert absolute.closed and absolute.style == "#ff0000"
    assert absolute.width[0] == pytest.approx(1.0)  # stroke-width scaled by the transform
    assert absolute.points[:, 0].max() == pytest.approx(300, abs=1e-6)
    # the absolute and relative paths draw the same shape, 50 units (x2) lower
    np.testing.assert_allclose(relative.points[:, 1].min() - 100, absolute.points[:, 1].min(),
                               atol=1e-6)
    # the arc A10 10 ... from (80,10) to (100,10) is a half circle of radius 10 about (90,10)
    arc = absolute.points[(absolute.points[:, 0] > 260 + 1e-6) & (absolute.points[:, 1] < 20)]
    radius = np.hypot(arc[:, 0] - 280, arc[:, 1] - 20)
    np.testing.assert_allclose(radius, 20, atol=0.05)
    assert not sk.strokes[2].closed and len(sk.strokes[2]) == 3  # polyline stays open
    assert sk.strokes[3].closed  # a polygon closes back on its first point
    np.testing.assert_allclose(sk.strokes[3].points[[0, -1]], [[0, 100], [0, 100]])
    np.testing.assert_allclose(sk.strokes[4].points, [[0, 150], [50, 150]])


def test_svg_curves_are_sampled_to_the_tolerance():
    data = b'<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C0 100 100 100 100 0"/></svg>'
    coarse = parse_svg(data, tolerance=1.0).strokes[0].points
    fine = parse_svg(data, tolerance=0.01).strokes[0].points
    assert len(fine) > 3 * len(coarse)
    t = np.linspace(0, 1, 2001)[:, None]
    exact = (3 * (1 - t) ** 2 * t * np.array([0, 100]) + 3 * (1 - t) * t**2 * np.array([100, 100])
             + t**3 * np.array([100, 0]))
    # every point of the exact curve is within the tolerance of the sampled polyline
    import shapely
    line = shapely.LineString(coarse)
    assert shapely.distance(shapely.points(exact), line).max() <= 1.0


@pytest.mark.parametrize("data, message", [
    (b"<svg", "well-formed"),
    (b'<svg xmlns="http://www.w3.org/2000/svg"><rect width="0" height="0"/></svg>', "drawable"),
    (b'<svg xmlns="http://www.w3.org/2000/svg"><text>hi</text></svg>', "drawable"),
    (b'<?xml version="1.0"?><!DOCTYPE x [<!ENTITY a "aaaa"><!ENTITY b "&a;&a;">]>'
     b'<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 L1 1"/>&b;</svg>', "unsafe"),
])
def test_svg_errors_are_clear(data, message):
    with pytest.raises(SketchError, match=message):
        parse_svg(data)


def test_svg_writer_round_trips_polylines_and_beziers(tmp_path):
    bez = np.array([[0, 0], [0, 10], [10, 10], [10, 0], [10, -10], [20, -10], [20, 0]], float)
    sketch = Sketch([
        Stroke([[0, 0], [5, 5], [10, 0]], width=2.0, style="#00ff00"),
        Stroke(np.array([[0, 0], [20, 0]]), bezier=bez),
    ])
    path = tmp_path / "out.svg"
    write_sketch(sketch, path)
    text = path.read_text()
    assert text.count("<path") == 2 and " C" in text.replace("\"C", " C")
    again = read_sketch(path)
    np.testing.assert_allclose(again.strokes[0].points, sketch.strokes[0].points)
    assert again.strokes[0].style == "#00ff00"
    # the Bezier comes back as its curve: passes through the joints and ends
    pts = again.strokes[1].points
    for joint in bez[::3]:
        assert np.hypot(*(pts - joint).T).min() < 1e-6


def test_read_sketch_dispatch_and_errors(tmp_path):
    with pytest.raises(SketchError, match="no such file"):
        read_sketch(tmp_path / "missing.scap")
    with pytest.raises(SketchError, match="unknown sketch format"):
        read_sketch(tmp_path / "x.png")
    binary = tmp_path / "bad.scap"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(SketchError):
        read_sketch(binary)
    svg = read_sketch(SAMPLES / "fish.svg")
    scap = read_sketch(SAMPLES / "fish.scap")
    assert len(svg.strokes) == len(scap.strokes)


def test_importing_core_loads_no_svg_reader():
    """The Blender add-on imports core and reads no files: svgelements and defusedxml are
    imported on the first SVG read, not before."""
    code = ("import sys, core; print('svgelements' in sys.modules, 'defusedxml' in sys.modules); "
            "core.read_sketch(sys.argv[1]); print('svgelements' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code, str(SAMPLES / "fish.svg")], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout.split()
    assert out == ["False", "False", "True"]
