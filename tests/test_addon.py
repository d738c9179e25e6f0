"""The Blender extension on the real Blender API (the bpy wheel)."""

from __future__ import annotations

import time

import bpy
import numpy as np
import pytest
import shapely
from blender_scene import (
    GP_DATA,
    SCALE,
    clear_scene,
    drawn_strokes,
    fill_drawing,
    load_extension,
    make_object,
    sample_points,
    snapshot,
)

from core import EPSILON_SOFT_MAX
from core.arrays.geometry import lines_from


@pytest.fixture(scope="module", autouse=True)
def extension():
    module = load_extension()
    module.register()
    yield module
    module.unregister()  # Blender 4.5 hangs at exit with an operator still registered


@pytest.fixture(autouse=True)
def empty_scene():
    clear_scene()
    bpy.context.scene.frame_set(1)
    yield


def strokes_of(drawing) -> list[np.ndarray]:
    attrs = drawing.attributes
    n = attrs.domain_size("POINT")
    pos = np.empty(n * 3, np.float32)
    attrs["position"].data.foreach_get("vector", pos)
    offsets = np.empty(attrs.domain_size("CURVE") + 1, np.int32)
    drawing.curve_offsets.foreach_get("value", offsets)
    return np.split(pos.reshape(-1, 3), offsets[1:-1])


def evaluated(drawing) -> np.ndarray:
    """Points along all the drawing's strokes, Beziers evaluated from knots and handles."""
    return np.concatenate(drawn_strokes(drawing))


def test_register_twice_and_operator_exists(extension):
    extension.register()
    assert hasattr(bpy.types, "SKETCHSIMP_OT_simplify")
    assert hasattr(bpy.types.Scene, "sketchsimp")


def test_current_frame_to_a_new_layer_leaves_the_source_untouched():
    ob = make_object({1: "house"})
    source = ob.data.layers["Lines"]
    before = snapshot(source.frames[0].drawing)
    assert bpy.ops.sketchsimp.simplify(epsilon=0.015) == {"FINISHED"}
    assert snapshot(source.frames[0].drawing) == before
    out_layer = ob.data.layers["Lines simplified"]
    assert source.hide and not out_layer.hide
    out = out_layer.frames[0].drawing
    n_in, n_out = len(strokes_of(source.frames[0].drawing)), len(strokes_of(out))
    assert 0 < n_out < n_in
    # Bezier strokes with handles, radius and opacity written (not Blender's zero defaults)
    attrs = out.attributes
    types = np.empty(attrs.domain_size("CURVE"), np.int8)
    attrs["curve_type"].data.foreach_get("value", types)
    assert (types == 2).all()
    radius = np.empty(attrs.domain_size("POINT"), np.float32)
    attrs["radius"].data.foreach_get("value", radius)
    np.testing.assert_allclose(radius, 0.01, rtol=1e-3)
    assert "handle_left" in attrs and "handle_right" in attrs
    # the Bezier curves (knots and handles) lie on the ink, on the drawing's plane
    ink = shapely.union_all(lines_from([s[:, [0, 2]] for s in sample_points("house")]))
    curve = evaluated(out)
    np.testing.assert_allclose(curve[:, 1], 0.0, atol=1e-5)
    assert shapely.distance(shapely.points(curve[:, [0, 2]]), ink).max() < 6 * SCALE
    last_run = bpy.context.scene.sketchsimp.last_run
    assert last_run.startswith("Simplified 1 drawing")
    # the panel and the report give the bundle width used: auto (Bundle Width 0), which
    # for the house's sparse ink is the widest, 1.5% of the drawing's diagonal
    def reported_width() -> float:
        text = bpy.context.scene.sketchsimp.last_run
        return float(text.split("bundle width ")[1].split()[0].rstrip(",;"))

    diagonal = np.hypot(*np.ptp(np.concatenate(sample_points("house"))[:, [0, 2]], axis=0))
    assert reported_width() == pytest.approx(0.015 * diagonal, rel=0.01)
    source.hide = False  # to simplify it again
    assert bpy.ops.sketchsimp.simplify(alpha=0.02) == {"FINISHED"}  # a number overrides
    assert reported_width() == pytest.approx(0.02 * diagonal, rel=0.01)


def test_all_keyframes_and_a_shared_drawing():
    ob = make_object({1: "house", 10: "cup"})
    layer = ob.data.layers["Lines"]
    layer.frames.copy(10, 20, instance_drawing=True)
    assert bpy.ops.sketchsimp.simplify(scope="ALL") == {"FINISHED"}
    out = ob.data.layers["Lines simplified"]
    assert sorted(f.frame_number for f in out.frames) == [1, 10, 20]
    by_frame = {f.frame_number: len(strokes_of(f.drawing)) for f in out.frames}
    assert by_frame[10] == by_frame[20] > 0 and by_frame[1] > 0
    shared = {f.frame_number: f.drawing.as_pointer() for f in out.frames}
    assert shared[10] == shared[20] != shared[1]  # still one drawing for both keyframes
    assert "2 drawing(s)" in bpy.context.scene.sketchsimp.last_run  # shared: simplified once


def test_replace_in_place():
    ob = make_object({1: "fish"})
    drawing = ob.data.layers["Lines"].frames[0].drawing
    n_in = len(strokes_of(drawing))
    assert bpy.ops.sketchsimp.simplify(output="REPLACE") == {"FINISHED"}
    assert 0 < len(strokes_of(drawing)) < n_in
    assert len(ob.data.layers) == 1


def test_new_object_output():
    ob = make_object({1: "cup"})
    assert bpy.ops.sketchsimp.simplify(output="OBJECT", hide_source=False) == {"FINISHED"}
    made = bpy.data.objects["Sketch simplified"]
    assert made.type == "GREASEPENCIL" and len(made.data.materials) == 1
    assert len(strokes_of(made.data.layers[0].frames[0].drawing)) > 0
    assert not ob.data.layers["Lines"].hide


def test_no_active_object_or_wrong_type_fails_poll():
    bpy.context.view_layer.objects.active = None
    assert not bpy.ops.sketchsimp.simplify.poll()
    with pytest.raises(RuntimeError, match="objects.active, or run scripts/batch_simplify"):
        bpy.ops.sketchsimp.simplify()  # headless: says how to name the object
    mesh = bpy.data.objects.new("Mesh", bpy.data.meshes.new("Mesh"))
    bpy.context.scene.collection.objects.link(mesh)
    bpy.context.view_layer.objects.active = mesh
    assert not bpy.ops.sketchsimp.simplify.poll()
    with pytest.raises(RuntimeError, match="poll"):
        bpy.ops.sketchsimp.simplify()


@pytest.mark.parametrize("case", ["empty", "one_point", "locked", "hidden"])
def test_bad_input_reports_and_changes_nothing(case):
    ob = make_object({1: None if case in ("empty", "one_point") else "house"})
    layer = ob.data.layers["Lines"]
    if case == "one_point":
        fill_drawing(layer.frames[0].drawing, [np.zeros((1, 3), np.float32)] * 3)
    layer.lock = case == "locked"
    layer.hide = case == "hidden"
    before = snapshot(layer.frames[0].drawing)
    why = {"empty": "an empty keyframe", "one_point": "only strokes of one point",
           "locked": "locked: unlock it", "hidden": "hidden: show it"}[case]
    with pytest.raises(RuntimeError, match=f"Nothing to simplify.*{why}"):
        bpy.ops.sketchsimp.simplify()
    assert len(ob.data.layers) == 1
    assert snapshot(layer.frames[0].drawing) == before


def test_extension_package_installs_and_runs(tmp_path):
    """The zip Blender's own builder makes installs, enables and works from the copy."""
    import json
    import os
    import platform
    import subprocess
    import sys

    from helpers import ROOT

    build = subprocess.run([sys.executable, str(ROOT / "scripts" / "build_extension.py"),
                            "--output-dir", str(tmp_path / "dist")],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr[-2000:]
    arch = "arm64" if platform.machine() in ("aarch64", "arm64") else "x64"
    package = tmp_path / "dist" / f"sketchsimp-0.1.0-linux_{arch}.zip"
    assert package.exists()
    import zipfile

    names = zipfile.ZipFile(package).namelist()
    assert "core/simplify.py" in names and "core/merge/agglomeration.py" in names
    assert not [n for n in names if n.startswith("core/cli/") or n in (
        "core/__main__.py", "core/cluster.py", "core/remote.py")]
    assert not [n for n in names if "dask" in n or "distributed" in n]
    env = {**os.environ, "BLENDER_USER_RESOURCES": str(tmp_path / "user"),
           "XDG_CACHE_HOME": str(tmp_path / "cache")}
    run = subprocess.run([sys.executable, str(ROOT / "tests" / "installed_extension.py"),
                          str(package), str(ROOT / "tests")], capture_output=True, text=True,
                         env=env, cwd=tmp_path, timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    info = json.loads(run.stdout.strip().splitlines()[-1])
    assert info["module"] and str(tmp_path / "user") in info["module"]
    assert info["enabled"] == [True, True]
    assert info["result"] == ["FINISHED"] and info["strokes_out"] > 0
    assert info["frames_out"] == 5
    # the bundled wheels were installed for the extension (Blender has no shapely)
    assert "shapely-2.1.2.dist-info" in info["wheels"]
    # no SVG reader: the add-on reads no files (svgelements would add a top-level "test")
    assert not [w for w in info["wheels"] if w.startswith(("svgelements", "defusedxml"))]


def test_a_stray_mark_far_away_on_the_layer_changes_nothing_of_the_drawing():
    house = sample_points("house")
    size = float(np.hypot(*np.ptp(np.concatenate(house)[:, [0, 2]], axis=0)))
    mark = np.array([[20 * size, 0, 0], [20 * size + 0.05 * size, 0, 0.01 * size]], np.float32)
    drawn = []
    for name, extra in (("Alone", []), ("Stray", [mark])):
        ob = make_object({1: None}, name=name)
        fill_drawing(ob.data.layers["Lines"].frames[0].drawing, house + extra)
        bpy.context.view_layer.objects.active = ob
        assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
        out = strokes_of(ob.data.layers["Lines simplified"].frames[0].drawing)
        drawn.append([s for s in out if float(s[:, 0].min()) < 10 * size])
        assert len(out) == len(drawn[-1]) + len(extra)  # the mark is a stroke of its own
        for other in bpy.data.objects:
            other.select_set(False)
    alone, stray = drawn
    assert len(stray) == len(alone)  # the house simplified as it was alone
    for a, b in zip(alone, stray):
        assert a.shape == b.shape and np.abs(a - b).max() < 1e-4 * size


def test_an_empty_keyframe_stays_empty_in_the_output():
    ob = make_object({1: "house", 10: "cup", 20: None, 30: "fish"})
    assert bpy.ops.sketchsimp.simplify(scope="ALL") == {"FINISHED"}
    out = ob.data.layers["Lines simplified"]
    assert sorted(f.frame_number for f in out.frames) == [1, 10, 20, 30]
    for number, empty in ((25, True), (20, True), (10, False), (30, False)):
        shown = out.get_frame_at(number).drawing.attributes.domain_size("CURVE")
        assert (shown == 0) == empty, number  # nothing of the cup shows through at 20-29


def test_an_object_of_only_empty_keyframes_is_named_with_the_reason():
    """All Keyframes over a layer whose keyframes are all empty: nothing is written, and
    the report says which layer and why, not "no strokes found"."""
    ob = make_object({1: None, 10: None})
    with pytest.raises(RuntimeError, match="layer 'Lines' \\(only empty keyframes: 2\\)"):
        bpy.ops.sketchsimp.simplify(scope="ALL")
    assert [x.name for x in ob.data.layers] == ["Lines"]


def test_selected_strokes_to_a_new_layer_leave_the_rest_of_the_source_in_view():
    ob = make_object({1: "house"})
    drawing = ob.data.layers["Lines"].frames[0].drawing
    chosen = np.zeros(len(strokes_of(drawing)), bool)
    chosen[:5] = True
    sel = drawing.attributes.new(".selection", "BOOLEAN", "CURVE")
    sel.data.foreach_set("value", chosen)
    assert bpy.ops.sketchsimp.simplify(scope="SELECTED", hide_source=True) == {"FINISHED"}
    assert not ob.data.layers["Lines"].hide  # the unselected strokes are still seen
    assert ob.data.layers["Lines simplified"].frames[0].drawing.attributes.domain_size(
        "CURVE") > 0


def test_nothing_selected_says_so():
    ob = make_object({1: "house"})
    drawing = ob.data.layers["Lines"].frames[0].drawing
    sel = drawing.attributes.new(".selection", "BOOLEAN", "CURVE")
    sel.data.foreach_set("value", np.zeros(len(strokes_of(drawing)), bool))
    with pytest.raises(RuntimeError, match="no stroke selected"):
        bpy.ops.sketchsimp.simplify(scope="SELECTED")


def test_the_new_strokes_stay_selected_after_selected_and_replace():
    ob = make_object({1: "house"})
    drawing = ob.data.layers["Lines"].frames[0].drawing
    n = len(strokes_of(drawing))
    chosen = np.zeros(n, bool)
    chosen[:5] = True
    sel = drawing.attributes.new(".selection", "BOOLEAN", "CURVE")
    sel.data.foreach_set("value", chosen)
    assert bpy.ops.sketchsimp.simplify(scope="SELECTED", output="REPLACE") == {"FINISHED"}
    after = drawing.attributes[".selection"]
    flags = np.empty(drawing.attributes.domain_size("CURVE"), bool)
    after.data.foreach_get("value", flags)
    assert not flags[:n - 5].any()  # the strokes left alone stay unselected
    assert flags[n - 5:].all() and len(flags) > n - 5  # what replaced the selection is


def test_a_drawing_that_is_not_flat_is_flattened_with_a_warning(capsys):
    ob = make_object({1: None})
    rng = np.random.default_rng(1)
    house = sample_points("house")
    bent = [s + np.array([0, 1, 0], np.float32) * rng.uniform(-0.3, 0.3) for s in house]
    fill_drawing(ob.data.layers["Lines"].frames[0].drawing, bent)
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    message = bpy.context.scene.sketchsimp.last_run
    assert "not flat" in message and "% of its size" in message
    flat = make_object({1: "house"}, name="Flat")
    bpy.context.view_layer.objects.active = flat
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    assert "not flat" not in bpy.context.scene.sketchsimp.last_run


def test_pressing_again_on_the_hidden_source_says_it_was_simplified():
    make_object({1: "house"})
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}  # hides the source layer
    with pytest.raises(RuntimeError, match="simplified before into 'Lines simplified'"):
        bpy.ops.sketchsimp.simplify()


def test_pressing_again_with_the_source_shown_replaces_the_earlier_result():
    """Shown again and simplified again (at another epsilon), the source's result layer is
    rewritten, not stacked under another, and is not taken for a source itself."""
    ob = make_object({1: "house", 5: "cup"})
    assert bpy.ops.sketchsimp.simplify(scope="ALL") == {"FINISHED"}
    first = {f.frame_number: len(strokes_of(f.drawing))
             for f in ob.data.layers["Lines simplified"].frames}
    ob.data.layers["Lines"].hide = False
    assert bpy.ops.sketchsimp.simplify(scope="ALL", layers="VISIBLE", epsilon=0.0) == {
        "FINISHED"}
    assert [x.name for x in ob.data.layers] == ["Lines", "Lines simplified"]
    again = ob.data.layers["Lines simplified"]
    assert sorted(f.frame_number for f in again.frames) == [1, 5]
    drawn = {f.frame_number: len(strokes_of(f.drawing)) for f in ob.data.layers["Lines"].frames}
    # epsilon 0 gives each stroke back: the frames hold the new run's strokes only
    assert {f.frame_number: len(strokes_of(f.drawing)) for f in again.frames} == drawn
    assert all(first[k] < drawn[k] for k in first)
    # the earlier result is rewritten, not a layer skipped: no warning
    last = bpy.context.scene.sketchsimp.last_run
    assert "rewrote 'Lines simplified'" in last and "skipped" not in last


def test_a_layer_in_a_group_gets_its_result_in_that_group_just_above_it():
    ob = make_object({1: "house"})
    gp = ob.data
    group = gp.layer_groups.new("Characters")
    below = gp.layers.new("Under", layer_group=group)
    gp.layers.move_to_layer_group(gp.layers["Lines"], group)
    gp.layers.new("On top", layer_group=group)
    gp.layers.new("Root")
    gp.layers.active = gp.layers["Lines"]
    order = [x.name for x in gp.layers]
    assert bpy.ops.sketchsimp.simplify(fill_regions=True) == {"FINISHED"}
    dest = gp.layers["Lines simplified"]
    assert dest.parent_group == group and gp.layers["Lines fills"].parent_group == group
    names = [x.name for x in gp.layers]
    at = names.index("Lines")
    assert names[at:at + 3] == ["Lines", "Lines fills", "Lines simplified"], names
    assert [n for n in names if n not in ("Lines fills", "Lines simplified")] == order
    assert below.parent_group == group
    group.hide = True  # hiding the group hides the result too
    assert all(not x.parent_group or x.parent_group.hide for x in gp.layers
               if x.name.startswith("Lines"))


def test_the_new_layer_is_drawn_as_the_source_layer():
    ob = make_object({1: "house"})
    layer = ob.data.layers["Lines"]
    layer.opacity, layer.blend_mode = 0.6, "MULTIPLY"
    layer.tint_color, layer.tint_factor, layer.use_lights = (0.2, 0.4, 0.9), 0.5, False
    assert bpy.ops.sketchsimp.simplify(hide_source=False) == {"FINISHED"}
    dest = ob.data.layers["Lines simplified"]
    assert dest.opacity == pytest.approx(0.6) and dest.blend_mode == "MULTIPLY"
    assert tuple(dest.tint_color) == pytest.approx((0.2, 0.4, 0.9))
    assert dest.tint_factor == pytest.approx(0.5) and not dest.use_lights


def test_a_point_at_1e30_is_left_out_with_a_note():
    ob = make_object({1: None})
    house = sample_points("house")
    house[3] = house[3].copy()
    house[3][5] = (1e30, 0.0, 0.0)
    fill_drawing(ob.data.layers["Lines"].frames[0].drawing, house)
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    assert "1 point(s) far outside the drawing" in bpy.context.scene.sketchsimp.last_run
    out = np.concatenate(strokes_of(ob.data.layers["Lines simplified"].frames[0].drawing))
    size = float(np.hypot(*np.ptp(np.concatenate(sample_points("house")), axis=0)[[0, 2]]))
    assert np.abs(out).max() < 10 * size  # the drawing, not 1e30 wide


def test_frame_range_simplifies_what_the_scene_shows():
    ob = make_object({1: "house", 10: "cup", 20: "fish", 30: "house"})
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end, scene.use_preview_range = 12, 25, False
    assert bpy.ops.sketchsimp.simplify(scope="RANGE", hide_source=False) == {"FINISHED"}
    out = ob.data.layers["Lines simplified"]
    assert sorted(f.frame_number for f in out.frames) == [10, 20]  # 10 shows at 12
    gp = ob.data
    gp.layers.remove(out)
    scene.use_preview_range = True
    scene.frame_preview_start, scene.frame_preview_end = 25, 40
    assert bpy.ops.sketchsimp.simplify(scope="RANGE", hide_source=False) == {"FINISHED"}
    assert sorted(f.frame_number for f in gp.layers["Lines simplified"].frames) == [20, 30]
    scene.use_preview_range = False


def test_hide_source_with_a_frame_range_never_blanks_a_frame():
    """Keyframes outside the range are shown on the result layer as drawn: at every frame
    the result layer shows the keyframe the source showed (simplified inside the range,
    as drawn outside it), never nothing and never a later keyframe's result."""
    ob = make_object({1: "house", 10: "cup", 20: "fish", 30: "house"})
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end, scene.use_preview_range = 12, 25, False
    assert bpy.ops.sketchsimp.simplify(scope="RANGE") == {"FINISHED"}
    source, out = ob.data.layers["Lines"], ob.data.layers["Lines simplified"]
    assert source.hide and not out.hide
    for frame in range(1, 36):
        assert out.get_frame_at(frame).frame_number == source.get_frame_at(frame).frame_number
    drawn = {f.frame_number: len(strokes_of(f.drawing)) for f in source.frames}
    shown = {f.frame_number: len(strokes_of(f.drawing)) for f in out.frames}
    assert shown[1] == drawn[1] and shown[30] == drawn[30]  # outside: as drawn
    assert shown[10] < drawn[10] and shown[20] < drawn[20]  # inside: simplified
    scene.frame_start, scene.frame_end = 1, 250


def fill_of(drawing, ob) -> list[tuple[int, str]]:
    """(points, material name) of each stroke of a drawing."""
    attrs = drawing.attributes
    n = attrs.domain_size("CURVE")
    index = np.zeros(n, np.int32)
    if attrs.get("material_index") is not None:
        attrs["material_index"].data.foreach_get("value", index)
    return [(len(s), ob.data.materials[int(k)].name) for s, k in zip(strokes_of(drawing), index)]


@pytest.mark.parametrize("output", ["LAYER", "REPLACE", "OBJECT"])
def test_fill_regions_writes_fills_under_the_lines(output):
    ob = make_object({1: "cup", 5: "house"})
    assert bpy.ops.sketchsimp.simplify(scope="ALL", output=output, fill_regions=True,
                                       hide_source=False) == {"FINISHED"}
    target = bpy.data.objects["Sketch simplified"] if output == "OBJECT" else ob
    names = [x.name for x in target.data.layers]  # bottom to top
    lines = "Lines" if output == "REPLACE" else "Lines simplified"
    assert names.index("Lines fills") == names.index(lines) - 1  # just under the lines
    fills = target.data.layers["Lines fills"]
    assert sorted(f.frame_number for f in fills.frames) == [1, 5]
    strokes = fill_of(fills.frames[0].drawing, target)
    assert strokes and all(name == "SketchSimp Fill" for _, name in strokes)
    mat = bpy.data.materials["SketchSimp Fill"].grease_pencil
    assert mat.show_fill and not mat.show_stroke


def test_a_hole_in_a_region_stays_a_hole():
    ob = make_object({1: None})
    t = np.linspace(0, 1, 40, dtype=np.float32)[:, None]

    def square(lo: float, hi: float, wobble: float) -> list[np.ndarray]:
        side = [(lo, lo, hi, lo), (hi, lo, hi, hi), (hi, hi, lo, hi), (lo, hi, lo, lo)]
        return [np.hstack([x0 + (x1 - x0) * t, np.full_like(t, wobble),
                           z0 + (z1 - z0) * t]) for x0, z0, x1, z1 in side]

    fill_drawing(ob.data.layers["Lines"].frames[0].drawing,
                 square(0.0, 1.0, 0.0) + square(0.35, 0.65, 0.0))
    assert bpy.ops.sketchsimp.simplify(fill_regions=True) == {"FINISHED"}
    strokes = fill_of(ob.data.layers["Lines fills"].frames[0].drawing, ob)
    kinds = [name for _, name in strokes]
    # the ring with its hole cut out; the inner square is the hole, left empty
    assert kinds == ["SketchSimp Fill", "SketchSimp Hole"]
    assert bpy.data.materials["SketchSimp Hole"].grease_pencil.use_fill_holdout


def rendered_alpha(size: tuple[int, int], ortho: float, path) -> np.ndarray:
    """The scene rendered by Workbench from the front (looking along +Y, orthographic,
    ``ortho`` wide), transparent film: whether each pixel is covered, rows top down."""
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    cam.data.type, cam.data.ortho_scale = "ORTHO", ortho
    cam.location, cam.rotation_euler = (0.0, -10.0, 0.0), (np.pi / 2, 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(path))
    px = np.empty(img.size[0] * img.size[1] * 4, np.float32)
    img.pixels.foreach_get(px)
    rows, cols = img.size[1], img.size[0]
    bpy.data.images.remove(img)
    return px.reshape(rows, cols, 4)[::-1, :, 3] > 0.5


@pytest.mark.parametrize("part", ["shapes", "pupils"])
def test_fills_rendered_cover_the_regions_and_keep_the_holes(tmp_path, part):
    """A ring, a figure-eight and a face with two eyes and their pupils, simplified with
    Fill Regions and rendered by Workbench (the fills layer alone): counted pixel by
    pixel, the ring and both loops of the eight are painted and the ring's hole is not;
    the face is painted but for its eyes, nothing outside the lines; and (``part``
    "pupils") the pupils are painted again (the even-odd rule)."""
    t = np.linspace(0, 2 * np.pi, 160)

    def circle(r: float, x: float, z: float = 0.0) -> np.ndarray:
        return np.stack([x + r * np.cos(t), 0 * t, z + r * np.sin(t)], axis=1)

    eight = np.stack([1.0 * np.sin(t), 0 * t, 0.6 * np.sin(2 * t)], axis=1)
    shapes = [circle(1.0, -3.0), circle(0.5, -3.0), eight, circle(1.0, 3.0),
              circle(0.3, 2.55, 0.3), circle(0.3, 3.45, 0.3), circle(0.13, 2.55, 0.3),
              circle(0.13, 3.45, 0.3)]
    ob = make_object({1: None})
    fill_drawing(ob.data.layers["Lines"].frames[0].drawing,
                 [s.astype(np.float32) for s in shapes], radius=0.004)
    assert bpy.ops.sketchsimp.simplify(fill_regions=True) == {"FINISHED"}
    for layer in ob.data.layers:
        layer.hide = layer.name != "Lines fills"
    width, height, ortho = 900, 300, 9.0
    alpha = rendered_alpha((width, height), ortho, tmp_path / "fills.png")
    px = ortho / width  # metres a pixel
    x = (np.arange(width) + 0.5) * px - ortho / 2
    z = ortho * height / width / 2 - (np.arange(height) + 0.5) * px
    x, z = np.meshgrid(x, z)

    def share(mask: np.ndarray) -> float:
        return float(alpha[mask].mean())

    def disc(r: float, cx: float, cz: float = 0.0, margin: float = 0.0) -> np.ndarray:
        return np.hypot(x - cx, z - cz) < r - margin

    m = 0.04  # keep clear of the lines, a few pixels
    assert share(disc(1.0, -3.0, margin=m) & ~disc(0.5 + m, -3.0)) > 0.97  # the ring
    assert share(disc(0.5, -3.0, margin=m)) < 0.02  # its hole
    loops = (np.abs(x) < 0.9) & (np.abs(z) < 0.1) & (np.abs(x) > 0.2)  # in each loop
    assert share(loops & (x < 0)) > 0.97 and share(loops & (x > 0)) > 0.97
    eyes = disc(0.3 + m, 2.55, 0.3) | disc(0.3 + m, 3.45, 0.3)
    assert share(disc(1.0, 3.0, margin=m) & ~eyes) > 0.97  # the face
    whites = (disc(0.3, 2.55, 0.3, m) & ~disc(0.13 + m, 2.55, 0.3)) | \
        (disc(0.3, 3.45, 0.3, m) & ~disc(0.13 + m, 3.45, 0.3))
    assert share(whites) < 0.02
    if part == "pupils":
        # the pupils, a circle about a bundle width across, each one closed line: their
        # fills are judged inside their clean lines (an open line has none)
        lines = [shapely.Polygon(p[:, [0, 2]]) for p in drawn_strokes(
            ob.data.layers["Lines simplified"].frames[0].drawing) if len(p) >= 3]
        for cx in (2.55, 3.45):
            pupil = min((g for g in lines if g.contains(shapely.Point(cx, 0.3))),
                        key=lambda g: g.area)
            assert pupil.area < 0.5 * np.pi * 0.3 ** 2  # the pupil's line, not the eye's
            assert share(shapely.contains_xy(pupil.buffer(-0.02), x, z)) > 0.97
        return
    drawn = disc(1.0 + m, -3.0) | disc(1.0 + m, 3.0) | (np.abs(x) < 1.0 + m) & (
        np.abs(z) < 0.6 + m)
    assert share(~drawn) < 0.001  # nothing outside the lines


@pytest.mark.parametrize("stable", [True, False])
def test_jittered_keyframes_keep_their_lines_when_stable(stable):
    """The same drawing redrawn with 0.5 px of jitter on five keyframes: held to each
    other, the outputs keep their stroke count within 2 and their lines in place."""
    rng = np.random.default_rng(0)
    house = sample_points("house")
    ob = make_object({k: None for k in (1, 2, 3, 4, 5)})
    for frame in ob.data.layers["Lines"].frames:
        fill_drawing(frame.drawing, [s + rng.normal(0, 0.5 * SCALE, s.shape).astype(np.float32)
                                     for s in house])
    assert bpy.ops.sketchsimp.simplify(scope="ALL", stable=stable) == {"FINISHED"}
    outs = [strokes_of(f.drawing) for f in ob.data.layers["Lines simplified"].frames]
    counts = [len(o) for o in outs]
    size = float(np.hypot(*np.ptp(np.concatenate(house)[:, [0, 2]], axis=0)))
    moved = []  # how far each output's points lie from the next one's, as a share of D
    for a, b in zip(outs[:-1], outs[1:]):
        pa, pb = np.concatenate(a)[:, [0, 2]], np.concatenate(b)[:, [0, 2]]
        moved.append(float(np.mean(shapely.distance(shapely.points(pa),
                                                    shapely.MultiPoint(pb)))) / size)
    if stable:  # consecutive outputs within 0.3% of D, stroke counts within 2
        assert max(counts) - min(counts) <= 2 and max(moved) < 0.003
    else:  # each keyframe on its own: the lines boil
        assert max(counts) - min(counts) > 2 or max(moved) >= 0.003


def test_a_redo_step_holds_again_only_the_keyframes_whose_lines_changed(monkeypatch):
    """Stable Across Frames on a shot, pressed at 0.02, then 0.01 (the redo panel), then
    0.02 again: the step back holds nothing again (every keyframe's lines are those held
    before) and writes what the first press wrote; held afresh, with nothing kept, the
    step to 0.01 gives what it gave."""
    from sketchsimp.core import ReplayCache
    from sketchsimp.core.curves.memo import LruStore
    from sketchsimp.sketchsimp_addon import run

    rng = np.random.default_rng(1)
    house = sample_points("house")
    jittered = [[s + rng.normal(0, 0.5 * SCALE, s.shape).astype(np.float32) for s in house]
                for _ in range(5)]

    def pressed(epsilon: float) -> list:
        clear_scene()
        ob = make_object({k: None for k in (1, 2, 3, 4, 5)})
        for frame, strokes in zip(ob.data.layers["Lines"].frames, jittered):
            fill_drawing(frame.drawing, strokes)
        assert bpy.ops.sketchsimp.simplify(scope="ALL", stable=True,
                                           epsilon=epsilon) == {"FINISHED"}
        return [strokes_of(f.drawing) for f in ob.data.layers["Lines simplified"].frames]

    calls = []
    held_to = run.held_to
    monkeypatch.setattr(run, "held_to", lambda *a: calls.append(1) or held_to(*a))
    monkeypatch.setattr(run, "HELD", LruStore(run.HELD_ENTRIES))
    first = pressed(0.02)
    assert len(calls) == 4  # each keyframe but the first, held to the one before
    step = pressed(0.01)
    calls.clear()
    back = pressed(0.02)
    assert calls == []
    assert all(len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b))
               for a, b in zip(back, first))
    monkeypatch.setattr(run, "HELD", LruStore(run.HELD_ENTRIES))
    monkeypatch.setattr(run, "REPLAY", ReplayCache())
    afresh = pressed(0.01)
    assert all(len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b))
               for a, b in zip(afresh, step))


def test_a_stepwise_run_holds_each_keyframe_once_as_soon_as_those_before_it_are_done(
        monkeypatch):
    """Stable Across Frames while the run goes on (run.Holding): after each drawing, the
    keyframes held are exactly those with every keyframe before them in their layer done,
    and their new strokes made; each is held and made once (finishing looks them up), and
    the strokes written are those that
    holding everything at the end gives."""
    from types import SimpleNamespace

    from sketchsimp.core import ReplayCache, SimplifyParams
    from sketchsimp.core.curves.memo import LruStore
    from sketchsimp.sketchsimp_addon import run

    rng = np.random.default_rng(2)
    house = sample_points("house")
    ob = make_object({k: None for k in (1, 2, 3, 4)})
    for frame in ob.data.layers["Lines"].frames:
        fill_drawing(frame.drawing, [s + rng.normal(0, 0.5 * SCALE, s.shape).astype(
            np.float32) for s in house])
    options = SimpleNamespace(scope="ALL", layers="ACTIVE", output="LAYER", hide_source=True,
                              as_curve=False, fill_regions=False, stable=True)
    calls, made = [], []
    held_to, to_new_strokes = run.held_to, run.to_new_strokes
    monkeypatch.setattr(run, "held_to", lambda *a: calls.append(1) or held_to(*a))
    monkeypatch.setattr(run, "to_new_strokes", lambda *a: made.append(1) or to_new_strokes(*a))
    monkeypatch.setattr(run, "HELD", LruStore(run.HELD_ENTRIES))
    monkeypatch.setattr(run, "REPLAY", ReplayCache())
    stepwise = run.StepwiseRun(ob, options, SimplifyParams(), 1, jobs=1)
    counts = []
    while not stepwise.done:
        stepwise.step()
        counts.append((len(calls), len(made)))
    # a drawing a step, in frame order: held as it comes, and its new strokes made then
    assert counts == [(0, 1), (1, 2), (2, 3), (3, 4)]
    results = stepwise.finish()
    assert len(calls) == 3 and len(made) == 4  # nothing left to hold or make at the end
    monkeypatch.setattr(run, "HELD", LruStore(run.HELD_ENTRIES))  # held afresh, at the end
    at_end = run.results_of(ob, options, stepwise.gathered, stepwise.outputs,
                            run.RunReport())
    assert len(calls) == 6
    assert [len(r.new.knots) for r in results] == [len(r.new.knots) for r in at_end]
    assert all(np.array_equal(a, b) for r, e in zip(results, at_end)
               for a, b in zip(r.new.knots, e.new.knots))


def test_a_drawing_moved_from_key_to_key_is_followed_when_stable():
    """The house moved 0.3% of its diagonal a keyframe along X over five keyframes: held
    to each other, the outputs keep their strokes and lie on each keyframe's own ink (the
    mean distance of the output to the ink no larger than on the first keyframe). Before,
    a kept stroke stayed put until a bundle width behind."""
    house = sample_points("house")
    size = float(np.hypot(*np.ptp(np.concatenate(house)[:, [0, 2]], axis=0)))
    ob = make_object({k: None for k in (1, 2, 3, 4, 5)})
    inks = []
    for k, frame in enumerate(ob.data.layers["Lines"].frames):
        shift = np.array([0.003 * size * k, 0.0, 0.0], dtype=np.float32)
        ink = [s + shift for s in house]
        fill_drawing(frame.drawing, ink)
        inks.append(np.concatenate(ink)[:, [0, 2]])
    assert bpy.ops.sketchsimp.simplify(scope="ALL", stable=True) == {"FINISHED"}
    outs = [strokes_of(f.drawing) for f in ob.data.layers["Lines simplified"].frames]
    off = [float(np.mean(shapely.distance(shapely.points(np.concatenate(o)[:, [0, 2]]),
                                          shapely.MultiPoint(ink)))) / size
           for o, ink in zip(outs, inks)]
    counts = [len(o) for o in outs]
    assert max(counts) - min(counts) <= 1
    assert max(off) < off[0] + 0.0005, off  # it moves with the ink


def test_selected_strokes_only():
    ob = make_object({1: "house"})
    drawing = ob.data.layers["Lines"].frames[0].drawing
    strokes = strokes_of(drawing)
    chosen = np.zeros(len(strokes), bool)
    chosen[:5] = True  # the floor and the right wall of the sample house
    sel = drawing.attributes.new(".selection", "BOOLEAN", "CURVE")
    sel.data.foreach_set("value", chosen)
    assert bpy.ops.sketchsimp.simplify(scope="SELECTED", output="REPLACE") == {"FINISHED"}
    after = strokes_of(drawing)
    # the unselected strokes are still there, unchanged, and the selected ones were merged
    kept = [s for s in after if any(len(s) == len(t) and np.array_equal(s, t)
                                    for t in strokes[5:])]
    assert len(kept) == len(strokes) - 5
    assert len(after) - len(kept) < 5
    selected_ink = shapely.union_all(lines_from([s[:, [0, 2]] for s in strokes[:5]]))
    new = [s for s in after if not any(len(s) == len(t) and np.array_equal(s, t)
                                       for t in strokes[5:])]
    assert shapely.distance(shapely.points(np.concatenate(new)[:, [0, 2]]),
                            selected_ink).max() < 6 * SCALE


def make_curve_object(sample: str, kind: str = "POLY"):
    """A curve object with one spline per stroke of a sample sketch (X-Z plane)."""
    cu = bpy.data.curves.new("Rough", type="CURVE")
    cu.dimensions = "3D"
    for pts in sample_points(sample):
        if kind in ("POLY", "NURBS"):
            sp = cu.splines.new(kind)
            sp.points.add(len(pts) - 1)
            sp.points.foreach_set("co", np.hstack([pts, np.ones((len(pts), 1),
                                                                np.float32)]).ravel())
        else:
            sp = cu.splines.new("BEZIER")
            sp.bezier_points.add(len(pts) - 1)
            bp = sp.bezier_points
            for key in ("co", "handle_left", "handle_right"):
                bp.foreach_set(key, pts.ravel())
    ob = bpy.data.objects.new("Rough", cu)
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.view_layer.objects.active = ob
    return ob


@pytest.mark.parametrize("kind", ["POLY", "BEZIER", "NURBS"])
def test_curve_object_in_and_bezier_curve_out(kind):
    ob = make_curve_object("cup", kind)
    ob.data.bevel_depth = 0.02
    ob.data.materials.append(bpy.data.materials.new("Tube"))
    n_in = len(ob.data.splines)
    assert bpy.ops.sketchsimp.simplify(hide_source=False) == {"FINISHED"}
    out = bpy.data.objects["Rough simplified"]
    assert out.type == "CURVE" and len(ob.data.splines) == n_in  # source untouched
    # drawn as the source: its bevel, its material, radius 1 (the bevel's multiplier)
    assert out.data.bevel_depth == pytest.approx(0.02)
    assert list(out.data.materials) == list(ob.data.materials)
    radius = np.concatenate([[p.radius for p in s.bezier_points] for s in out.data.splines])
    assert np.allclose(radius, 1.0)
    splines = out.data.splines
    assert 0 < len(splines) < n_in and all(s.type == "BEZIER" for s in splines)
    ink = shapely.union_all(lines_from([s[:, [0, 2]] for s in sample_points("cup")]))
    co = np.concatenate([[p.co[:] for p in s.bezier_points] for s in splines])
    assert shapely.distance(shapely.points(co[:, [0, 2]]), ink).max() < 6 * SCALE


def curve_snapshot(ob) -> list[bytes]:
    """Every spline's point buffers, to compare byte for byte."""
    out = []
    for sp in ob.data.splines:
        for seq, keys, size in ((sp.points, ("co",), 4),
                                (sp.bezier_points, ("co", "handle_left", "handle_right"), 3)):
            for key in keys:
                buf = np.empty(len(seq) * size, np.float32)
                seq.foreach_get(key, buf)
                out.append(buf.tobytes())
    return out


def test_odd_curve_splines_are_skipped_and_the_source_kept():
    """NaN points, one-point splines and a NURBS spline among good ones: the good ink is
    simplified, the report says what was read approximately, the source is unchanged."""
    ob = make_curve_object("cup", "POLY")
    odd = ob.data.splines.new("POLY")  # one point only
    odd.points.foreach_set("co", [0.0, 0.0, 0.0, 1.0])
    bad = ob.data.splines[0].points
    co = np.empty(len(bad) * 4, np.float32)
    bad.foreach_get("co", co)
    co[4:6] = np.nan
    bad.foreach_set("co", co)
    nurbs = ob.data.splines.new("NURBS")
    nurbs.points.add(3)
    nurbs.points.foreach_set("co", np.array([[0, 0, 0, 1], [1, 0, 1, 1], [2, 0, 0, 1],
                                             [3, 0, 1, 1]], np.float32).ravel())
    before = curve_snapshot(ob)
    assert bpy.ops.sketchsimp.simplify(hide_source=False) == {"FINISHED"}
    assert curve_snapshot(ob) == before
    out = bpy.data.objects["Rough simplified"].data.splines
    co = np.concatenate([[p.co[:] for p in s.bezier_points] for s in out])
    assert len(out) > 0 and np.isfinite(co).all()


def parent_to_a_moving_empty(layer, at: tuple, then: tuple):
    """Parent a layer to a new empty at ``at``, then move the empty to ``then``."""
    empty = bpy.data.objects.new("Rig", None)
    bpy.context.scene.collection.objects.link(empty)
    empty.location = at
    bpy.context.view_layer.update()
    layer.parent = empty
    empty.location = then
    bpy.context.view_layer.update()
    return empty


def curve_points_world(ob) -> np.ndarray:
    co = np.concatenate([[p.co[:] for p in s.bezier_points] for s in ob.data.splines])
    m = np.array(ob.matrix_world)
    return co @ m[:3, :3].T + m[:3, 3]


@pytest.mark.parametrize("parented", [False, True])
def test_grease_pencil_to_a_bezier_curve_object_that_renders_where_the_ink_is(parented):
    ob = make_object({1: "house"})
    layer = ob.data.layers["Lines"]
    if parented:  # the layer follows an empty 4.8 m away
        parent_to_a_moving_empty(layer, (4.8, 0.0, 0.0), (4.8, 0.0, 1.0))
    assert bpy.ops.sketchsimp.simplify(as_curve=True) == {"FINISHED"}
    out = bpy.data.objects["Sketch Lines simplified"]
    assert out.type == "CURVE" and len(out.data.splines) > 0
    assert len(ob.data.layers) == 1 and layer.hide
    # it renders: a bevel, a material with the ink's colour
    assert out.data.bevel_depth > 0 and len(out.data.materials) > 0
    assert tuple(out.data.materials[0].diffuse_color)[:3] == pytest.approx(
        tuple(ob.data.materials[0].grease_pencil.color)[:3])
    # where the layer's ink is in the world
    ink = np.concatenate(sample_points("house"))
    world = np.array(ob.matrix_world) if not parented else (
        np.array(layer.parent.matrix_world) @ np.array(layer.matrix_parent_inverse))
    ink_world = ink @ world[:3, :3].T + world[:3, 3]
    ink_lines = shapely.union_all(lines_from(
        [s @ world[:3, :3].T[:, [0, 2]] + world[:3, 3][[0, 2]] for s in sample_points("house")]))
    pts = curve_points_world(out)
    assert abs(pts[:, 1] - ink_world[:, 1].mean()).max() < 1e-4
    assert shapely.distance(shapely.points(pts[:, [0, 2]]), ink_lines).max() < 6 * SCALE
    # parented as the ink is: moving what the strokes follow moves the curve along
    mover = layer.parent if parented else ob
    assert out.parent == mover
    mover.location = tuple(np.array(mover.location) + (0.0, 0.0, 2.5))
    bpy.context.view_layer.update()
    np.testing.assert_allclose(curve_points_world(out), pts + (0.0, 0.0, 2.5), atol=1e-5)


def shown_curves(prefix: str) -> list:
    """The curve objects whose name starts with ``prefix`` that the viewport and a render
    show now."""
    return [o for o in bpy.data.objects if o.type == "CURVE" and o.name.startswith(prefix)
            and not o.hide_viewport and not o.hide_render]


@pytest.mark.parametrize("scope", ["ALL", "RANGE"])
def test_a_shot_as_curve_objects_plays_each_drawing_on_its_own_frames(scope):
    """Four keyframes (one drawing shared by frames 20 and 25) to curve objects: one curve
    object per drawing, and scrubbed frame by frame the shot shows, from each keyframe to
    the next, the one curve object of the drawing the source shows there (nothing before
    the first keyframe), in the viewport and in renders. With a frame range (12 to 22) the
    keyframes outside it are written as drawn, so that no frame goes blank with the source
    hidden; the source is hidden."""
    ob = make_object({1: "house", 10: "cup", 20: "fish", 30: "house"})
    layer = ob.data.layers["Lines"]
    layer.frames.copy(20, 25, instance_drawing=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end, scene.use_preview_range = 12, 22, False
    try:
        assert bpy.ops.sketchsimp.simplify(scope=scope, as_curve=True) == {"FINISHED"}
        prefix = "Sketch Lines simplified "
        made = sorted(o.name for o in bpy.data.objects if o.name.startswith(prefix))
        # with a range, 25 (outside it) is a keyframe as drawn, as on a result layer
        objects = (1, 10, 20, 30) if scope == "ALL" else (1, 10, 20, 25, 30)
        assert made == [prefix + f"{n:04d}" for n in objects]
        assert layer.hide
        drawn = {f.frame_number: strokes_of(f.drawing) for f in layer.frames}
        for frame in range(-2, 40):
            scene.frame_set(frame)
            shown = shown_curves(prefix)
            source = layer.get_frame_at(frame)
            if source is None:
                assert shown == [], frame
                continue
            assert len(shown) == 1, (frame, [o.name for o in shown])
            first = max(n for n in objects if n <= frame)
            assert shown[0].name == prefix + f"{first:04d}", frame
        # each object draws its own drawing: simplified within the scope, as drawn outside
        simplified = (1, 10, 20, 30) if scope == "ALL" else (10, 20)
        for n in objects:
            splines = len(bpy.data.objects[prefix + f"{n:04d}"].data.splines)
            if n in simplified:
                assert splines < len(drawn[n])
            else:
                assert splines == len(drawn[n])
    finally:
        scene.frame_start, scene.frame_end = 1, 250
        scene.frame_set(1)


def test_a_single_drawing_as_a_curve_object_is_one_object_always_shown():
    ob = make_object({1: "house"})
    assert bpy.ops.sketchsimp.simplify(as_curve=True) == {"FINISHED"}
    out = bpy.data.objects["Sketch Lines simplified"]
    assert out.animation_data is None and not out.hide_viewport
    assert ob.data.layers["Lines"].hide


def test_layers_in_hidden_or_locked_groups_are_left_alone():
    ob = make_object({1: "house"})
    layer = ob.data.layers["Lines"]
    for state in ("hide", "lock"):
        group = ob.data.layer_groups.new(f"Group {state}")
        ob.data.layers.move_to_layer_group(layer, group)
        setattr(group, state, True)
        before = snapshot(layer.frames[0].drawing)
        with pytest.raises(RuntimeError, match=f"group 'Group {state}'"):
            bpy.ops.sketchsimp.simplify(output="REPLACE")
        assert snapshot(layer.frames[0].drawing) == before
        assert [x.name for x in ob.data.layers] == ["Lines"]
        setattr(group, state, False)


@pytest.mark.parametrize("state", ["hide", "lock"])
def test_strokes_of_a_hidden_or_locked_material_are_left_alone(state):
    ob = make_object({1: "house"})
    drawing = ob.data.layers["Lines"].frames[0].drawing
    held = bpy.data.materials.new("Held")
    bpy.data.materials.create_gpencil_data(held)
    ob.data.materials.append(held)
    n = len(strokes_of(drawing))
    index = np.zeros(n, np.int32)
    index[:4] = 1  # the first four strokes use it
    attr = drawing.attributes.get("material_index") or drawing.attributes.new(
        "material_index", "INT", "CURVE")
    attr.data.foreach_set("value", index)
    kept = strokes_of(drawing)[:4]
    setattr(held.grease_pencil, state, True)
    assert bpy.ops.sketchsimp.simplify(output="REPLACE") == {"FINISHED"}
    after = strokes_of(drawing)
    for s in kept:  # still there, point for point
        assert any(len(s) == len(t) and np.array_equal(s, t) for t in after)


def test_visible_layers_each_get_a_layer_just_above():
    ob = make_object({1: "house"}, layer_name="Back")
    front = ob.data.layers.new("Front", set_active=True)
    from blender_scene import fill_drawing
    fill_drawing(front.frames.new(1).drawing, sample_points("cup"))
    hidden = ob.data.layers.new("Hidden")
    fill_drawing(hidden.frames.new(1).drawing, sample_points("fish"))
    hidden.hide = True
    assert bpy.ops.sketchsimp.simplify(layers="VISIBLE", hide_source=False) == {"FINISHED"}
    assert [x.name for x in ob.data.layers] == ["Back", "Back simplified", "Front",
                                                "Front simplified", "Hidden"]
    assert "layer 'Hidden' (hidden: show it" in bpy.context.scene.sketchsimp.last_run


def test_layer_transform_and_parent_are_kept_and_edit_mode_works():
    ob = make_object({1: "house"})
    layer = ob.data.layers["Lines"]
    layer.translation = (0.5, 0.0, 0.25)
    # the rig moved after the layer was parented
    empty = parent_to_a_moving_empty(layer, (1.0, 2.0, 3.0), (-2.0, 0.0, 1.0))
    bpy.context.view_layer.objects.active = ob
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
    out = ob.data.layers["Lines simplified"]
    assert out.parent == empty

    def world(lay):
        return np.array(empty.matrix_world @ lay.matrix_parent_inverse @ lay.matrix_local)

    np.testing.assert_allclose(world(out), world(layer), atol=1e-5)


def test_vertex_colour_opacity_and_material_are_carried_over():
    ob = make_object({1: "cup"})
    red = bpy.data.materials.new("Red")
    bpy.data.materials.create_gpencil_data(red)
    ob.data.materials.append(red)
    drawing = ob.data.layers["Lines"].frames[0].drawing
    attrs = drawing.attributes
    n, s = attrs.domain_size("POINT"), attrs.domain_size("CURVE")
    colour = attrs.new("vertex_color", "FLOAT_COLOR", "POINT")
    colour.data.foreach_set("color", np.tile([0.2, 0.4, 0.6, 1.0], n).astype(np.float32))
    attrs.new("material_index", "INT", "CURVE").data.foreach_set(
        "value", np.ones(s, np.int32))
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    out = ob.data.layers["Lines simplified"].frames[0].drawing.attributes
    m = out.domain_size("POINT")
    got = np.empty(m * 4, np.float32)
    out["vertex_color"].data.foreach_get("color", got)
    np.testing.assert_allclose(got.reshape(-1, 4), np.tile([0.2, 0.4, 0.6, 1.0], (m, 1)),
                               atol=1e-5)  # float32 means
    opacity = np.empty(m, np.float32)
    out["opacity"].data.foreach_get("value", opacity)
    np.testing.assert_allclose(opacity, 0.9, atol=1e-5)
    material = np.empty(out.domain_size("CURVE"), np.int32)
    out["material_index"].data.foreach_get("value", material)
    assert (material == 1).all()


def point_values(drawing, name: str, width: int = 1) -> list[np.ndarray]:
    """A point attribute of a drawing, split by stroke."""
    attrs = drawing.attributes
    values = np.empty(attrs.domain_size("POINT") * width, np.float32)
    attrs[name].data.foreach_get("color" if width == 4 else "value", values)
    offsets = np.empty(attrs.domain_size("CURVE") + 1, np.int32)
    drawing.curve_offsets.foreach_get("value", offsets)
    return np.split(values.reshape(-1, width) if width > 1 else values, offsets[1:-1])


def test_taper_opacity_and_colour_follow_the_ink_along_each_stroke():
    """A bundle of four long strokes, tapered (radius 0.002 at the ends, 0.02 in the
    middle), fading (opacity 0.2 to 1.0 along), two red and two blue: the output stroke is
    tapered at both ends, fades the same way, and every knot is red or blue, never a mix."""
    t = np.linspace(0, 1, 60)
    ob = make_object({1: None})
    strokes = [np.stack([4 * t, np.zeros_like(t), 0.3 * np.sin(3 * t) + 0.01 * k], axis=1)
               .astype(np.float32) for k in range(4)]
    drawing = ob.data.layers["Lines"].frames[0].drawing
    fill_drawing(drawing, strokes)
    attrs = drawing.attributes
    n = attrs.domain_size("POINT")
    taper = np.tile(0.002 + 0.018 * np.sin(np.pi * t), 4).astype(np.float32)
    attrs["radius"].data.foreach_set("value", taper)
    attrs["opacity"].data.foreach_set("value", np.tile(0.2 + 0.8 * t, 4).astype(np.float32))
    red, blue = [0.9, 0.1, 0.1, 1.0], [0.1, 0.1, 0.9, 1.0]
    colours = np.array([red] * 60 + [blue] * 60 + [red] * 60 + [blue] * 60, np.float32)
    attrs.new("vertex_color", "FLOAT_COLOR", "POINT").data.foreach_set("color", colours.ravel())
    assert n == 240
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    out = ob.data.layers["Lines simplified"].frames[0].drawing
    radii = point_values(out, "radius")
    assert len(radii) == 1 and len(radii[0]) >= 7
    r = radii[0]
    assert r.max() > 0.015 and r[0] < 0.3 * r.max() and r[-1] < 0.3 * r.max()  # tapered
    opacity = point_values(out, "opacity")[0]
    left_to_right = np.sign(strokes[0][-1, 0] - strokes[0][0, 0]) * np.sign(
        np.diff(strokes_of(out)[0][[0, -1], 0]))[0]
    o = opacity if left_to_right > 0 else opacity[::-1]
    assert o[0] < 0.35 and o[-1] > 0.85 and (np.diff(o) > -0.05).all()  # fades along
    got = point_values(out, "vertex_color", 4)[0]
    is_red = np.abs(got - red).max(axis=1) < 1e-6
    is_blue = np.abs(got - blue).max(axis=1) < 1e-6
    assert (is_red | is_blue).all()  # a colour of the ink, never a mix
    assert is_red.all() or is_blue.all()  # one bundle: its main colour only


def test_a_circle_drawn_half_red_half_blue_keeps_each_half_its_colour():
    """Two arcs, red and blue, drawn on from each other into one circle: one stroke whose
    knots are red over the red ink and blue over the blue, each a colour of the ink."""
    ob = make_object({1: None})
    t = np.linspace(-0.2, np.pi + 0.2, 80)
    arcs = [np.stack([np.cos(t + k * np.pi), np.zeros_like(t), np.sin(t + k * np.pi)],
                     axis=1).astype(np.float32) for k in range(2)]
    drawing = ob.data.layers["Lines"].frames[0].drawing
    fill_drawing(drawing, arcs)
    red, blue = [0.9, 0.1, 0.1, 1.0], [0.1, 0.1, 0.9, 1.0]
    colours = np.array([red] * 80 + [blue] * 80, np.float32)
    drawing.attributes.new("vertex_color", "FLOAT_COLOR", "POINT").data.foreach_set(
        "color", colours.ravel())
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    out = ob.data.layers["Lines simplified"].frames[0].drawing
    knots = strokes_of(out)
    assert len(knots) == 1
    got = point_values(out, "vertex_color", 4)[0]
    is_red = np.abs(got - red).max(axis=1) < 1e-6
    is_blue = np.abs(got - blue).max(axis=1) < 1e-6
    assert (is_red | is_blue).all()
    upper = knots[0][:, 2] > 0.3  # the red arc's side, away from where the two overlap
    lower = knots[0][:, 2] < -0.3
    assert upper.sum() >= 2 and lower.sum() >= 2
    assert is_red[upper].all() and is_blue[lower].all()


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_cancelled_stepwise_run_writes_the_drawings_it_finished_and_nothing_else(
        jobs, monkeypatch):
    """The modal operator's run, in this process a drawing a step (jobs 1) or in the kept
    pool (jobs 2): cancelled after two of four keyframes, the two are written whole and
    the other two left as they were; run to the end, it gives what the one-go run gives."""
    from types import SimpleNamespace

    from sketchsimp.core import ReplayCache, SimplifyParams
    from sketchsimp.sketchsimp_addon import run, write

    run.stop_kept_pool()  # nothing kept by other tests
    monkeypatch.setattr(run, "REPLAY", ReplayCache())
    ob = make_object({1: "house", 5: "cup", 9: "fish", 13: "house"})
    before = {f.frame_number: snapshot(f.drawing) for f in ob.data.layers["Lines"].frames}
    options = SimpleNamespace(scope="ALL", layers="ACTIVE", output="LAYER", hide_source=True,
                              as_curve=False, fill_regions=False, stable=False)
    stepwise = run.StepwiseRun(ob, options, SimplifyParams(), 1, jobs=jobs)
    assert stepwise.total == 4
    while stepwise.finished < 2:
        stepwise.step()
    done = sorted(f.frame_number for p, out in zip(stepwise.gathered.prepared,
                                                   stepwise.outputs)
                  if out is not None for f in p.frames)
    results = stepwise.finish()
    assert [r.frames[0].frame_number for r in results] == done
    if jobs == 1:
        assert done == [1, 5]  # in order, a drawing a step
    assert f"cancelled: {len(done)} of 4 drawing(s) done" in stepwise.report.message()
    write.write_results(ob, options, results, bpy.context)
    out = ob.data.layers["Lines simplified"]
    # the source is hidden: the ones not done are shown on the result layer as drawn
    assert sorted(f.frame_number for f in out.frames) == [1, 5, 9, 13]
    source = {f.frame_number: strokes_of(f.drawing) for f in ob.data.layers["Lines"].frames}
    shown = {f.frame_number: strokes_of(f.drawing) for f in out.frames}
    for k in set(source) - set(done):
        assert len(shown[k]) == len(source[k])
        assert all(np.allclose(a, b) for a, b in zip(shown[k], source[k]))
    for k in done:
        assert len(shown[k]) < len(source[k])
    assert {f.frame_number: snapshot(f.drawing)
            for f in ob.data.layers["Lines"].frames} == before
    whole = run.StepwiseRun(ob, options, SimplifyParams(), 1, jobs=jobs)
    while not whole.done:
        whole.step()
    monkeypatch.setattr(run, "REPLAY", ReplayCache())
    _, at_once = run.simplify_object(ob, options, SimplifyParams(), 1, jobs=1)
    assert [len(r.new.knots) for r in whole.finish()] == [len(r.new.knots) for r in at_once]


def test_invoked_without_a_window_the_operator_runs_at_once():
    ob = make_object({1: "house", 5: "cup", 9: "fish"})
    assert bpy.ops.sketchsimp.simplify("INVOKE_DEFAULT", scope="ALL") == {"FINISHED"}
    assert len(ob.data.layers["Lines simplified"].frames) == 3


def test_many_keyframes_go_through_the_process_pool():
    samples = ["house", "cup", "fish", "house", "cup"]
    ob = make_object({1 + 4 * k: name for k, name in enumerate(samples)})
    assert bpy.ops.sketchsimp.simplify(scope="ALL") == {"FINISHED"}  # 5 drawings: a pool
    pooled = {f.frame_number: strokes_of(f.drawing)
              for f in ob.data.layers["Lines simplified"].frames}
    clear_scene()
    from sketchsimp.sketchsimp_addon.run import simplify_object
    ob = make_object({1 + 4 * k: name for k, name in enumerate(samples)})

    class Options:
        scope, layers, fill_regions, as_curve, stable = "ALL", "ACTIVE", False, False, False

    from sketchsimp.core import SimplifyParams  # the extension's own copy of core
    report, results = simplify_object(ob, Options, SimplifyParams(), 1, jobs=1)
    assert report.drawings == 5 and len(pooled) == 5
    for r in results:  # the same strokes, one process or several
        assert len(r.new.knots) == len(pooled[r.frames[0].frame_number])


def test_a_batch_pool_already_started_takes_even_two_keyframes(monkeypatch):
    """A pool the caller keeps (a batch's, across files) runs two drawings already, where
    one started for them would cost more than it saves; the strokes are the same."""
    from sketchsimp.core import ReplayCache, SimplifyParams
    from sketchsimp.core.parallel import local_pool
    from sketchsimp.sketchsimp_addon import run

    class Options:
        scope, layers, fill_regions, as_curve, stable = "ALL", "ACTIVE", False, False, False

    ob = make_object({1: "house", 5: "cup"})
    _, here = run.simplify_object(ob, Options, SimplifyParams(), 1)  # 2 < POOL_FROM
    monkeypatch.setattr(run, "REPLAY", ReplayCache())  # nothing kept from that run
    with local_pool(2) as pool:
        queued = pool._queue_count  # work items sent to the workers so far
        _, pooled = run.simplify_object(ob, Options, SimplifyParams(), 1, pool=pool)
        assert pool._queue_count == queued + 2
    assert [len(r.new.knots) for r in pooled] == [len(r.new.knots) for r in here] != []


def test_an_epsilon_step_on_a_pooled_shot_replays_every_drawing_in_its_kept_worker(
        monkeypatch):
    """Five keyframes go through the kept pool; a new epsilon (the redo panel) goes back
    to the worker holding each drawing's result and replays it there (no merge loop run
    again, no base complex rebuilt), and gives what a fresh run at that epsilon gives.
    Once the pool is stopped, the merge records kept here rebuild the drawings in a new
    one."""
    from sketchsimp.core import ReplayCache, SimplifyParams
    from sketchsimp.sketchsimp_addon import run
    monkeypatch.setattr(run, "REPLAY", ReplayCache())
    run.stop_kept_pool()
    samples = ["house", "cup", "fish", "house", "cup"]
    keys = {1 + 4 * k: name for k, name in enumerate(samples)}
    ob = make_object(keys)
    assert bpy.ops.sketchsimp.simplify(scope="ALL", epsilon=0.02) == {"FINISHED"}
    assert run.REPLAY.runs == 0  # all in the pool
    pool = run.kept_pool(run.default_jobs())
    assert dict(pool.counts) == {"ran": 3}  # three distinct drawings
    clear_scene()
    ob = make_object(keys)  # as after the redo panel's undo
    t0 = time.perf_counter()
    assert bpy.ops.sketchsimp.simplify(scope="ALL", epsilon=0.01) == {"FINISHED"}
    replay_seconds = time.perf_counter() - t0
    assert run.REPLAY.runs == 0  # nothing run here
    assert dict(pool.counts) == {"ran": 3, "replayed": 3}
    replayed = {f.frame_number: strokes_of(f.drawing)
                for f in ob.data.layers["Lines simplified"].frames}
    run.stop_kept_pool()  # (idle too long): the records kept here rebuild them
    clear_scene()
    ob = make_object(keys)
    assert bpy.ops.sketchsimp.simplify(scope="ALL", epsilon=0.005) == {"FINISHED"}
    assert dict(run.kept_pool(run.default_jobs()).counts) == {"rebuilt": 3}
    monkeypatch.setattr(run, "REPLAY", ReplayCache())
    clear_scene()
    ob = make_object(keys)

    class Options:
        scope, layers, fill_regions, as_curve, stable = "ALL", "ACTIVE", False, False, True

    t0 = time.perf_counter()
    _, fresh = run.simplify_object(ob, Options, SimplifyParams(epsilon=0.01), 1, jobs=1)
    fresh_seconds = time.perf_counter() - t0
    assert run.REPLAY.runs == 3  # three distinct drawings run here afresh
    for r in fresh:
        got = replayed[r.frames[0].frame_number]
        assert len(got) == len(r.new.knots)
        assert all(np.allclose(a, b, atol=1e-5) for a, b in zip(got, r.new.knots))
    print(f"epsilon step replayed in {replay_seconds:.2f} s, fresh {fresh_seconds:.2f} s")


def test_nan_points_and_an_object_without_layers():
    ob = make_object({1: "house"})
    drawing = ob.data.layers["Lines"].frames[0].drawing
    attrs = drawing.attributes
    n = attrs.domain_size("POINT")
    pos = np.empty(n * 3, np.float32)
    attrs["position"].data.foreach_get("vector", pos)
    pos[3:9] = np.nan  # two points of the first stroke
    attrs["position"].data.foreach_set("vector", pos)
    before = snapshot(drawing)
    assert bpy.ops.sketchsimp.simplify() == {"FINISHED"}
    assert snapshot(drawing) == before
    out = evaluated(ob.data.layers["Lines simplified"].frames[0].drawing)
    assert np.isfinite(out).all()
    bare = bpy.data.objects.new("Bare", GP_DATA.new("Bare"))  # no layers at all
    bpy.context.scene.collection.objects.link(bare)
    bpy.context.view_layer.objects.active = bare
    with pytest.raises(RuntimeError, match="Nothing to simplify"):
        bpy.ops.sketchsimp.simplify()


def test_a_new_epsilon_in_the_redo_panel_is_a_replay(monkeypatch):
    from sketchsimp.core import ReplayCache
    from sketchsimp.sketchsimp_addon import run
    monkeypatch.setattr(run, "REPLAY", ReplayCache())  # nothing cached by other tests
    ob = make_object({1: "fish"})
    runs = run.REPLAY.runs
    assert bpy.ops.sketchsimp.simplify(epsilon=0.02, output="REPLACE") == {"FINISHED"}
    first = strokes_of(ob.data.layers["Lines"].frames[0].drawing)
    clear_scene()
    ob = make_object({1: "fish"})  # the same drawing again, as after an undo
    # (at 0, every stroke back: the fish's lines are the same from 0.0005 to 0.02)
    assert bpy.ops.sketchsimp.simplify(epsilon=0.0, output="REPLACE") == {"FINISHED"}
    assert run.REPLAY.runs == runs + 1  # the second epsilon was replayed, not re-run
    replayed = strokes_of(ob.data.layers["Lines"].frames[0].drawing)
    clear_scene()  # above the first epsilon: one run more, on to the slider's top ...
    ob = make_object({1: "fish"})
    assert bpy.ops.sketchsimp.simplify(epsilon=0.03, output="REPLACE") == {"FINISHED"}
    assert run.REPLAY.runs == runs + 2
    for eps in (EPSILON_SOFT_MAX, 0.045, 0.005):  # ... and every epsilon replays from then
        clear_scene()
        ob = make_object({1: "fish"})
        assert bpy.ops.sketchsimp.simplify(epsilon=eps, output="REPLACE") == {"FINISHED"}
    assert run.REPLAY.runs == runs + 2
    monkeypatch.setattr(run, "REPLAY", ReplayCache())  # the replayed epsilon, run afresh
    clear_scene()
    ob = make_object({1: "fish"})
    assert bpy.ops.sketchsimp.simplify(epsilon=0.0, output="REPLACE") == {"FINISHED"}
    assert run.REPLAY.runs == 1
    fresh = strokes_of(ob.data.layers["Lines"].frames[0].drawing)

    def same(a: list[np.ndarray], b: list[np.ndarray]) -> bool:
        return len(a) == len(b) and all(x.shape == y.shape and np.allclose(x, y, atol=1e-5)
                                        for x, y in zip(a, b))

    assert same(replayed, fresh) and not same(replayed, first)
