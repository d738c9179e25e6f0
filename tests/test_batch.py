"""Batch simplification: scripts/batch_simplify.py on .blend files, python -m core batch."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys

import bpy
import pytest
from blender_scene import clear_scene, fill_drawing, make_object, sample_points
from helpers import ROOT, SAMPLES

SCRIPT = ROOT / "scripts" / "batch_simplify.py"
INSPECT = """
import bpy, json, sys
bpy.ops.wm.open_mainfile(filepath=sys.argv[1])
out = {}
for ob in bpy.data.objects:
    if ob.type == "GREASEPENCIL":
        out[ob.name] = {l.name: {f.frame_number: f.drawing.attributes.domain_size("CURVE")
                                 for f in l.frames} for l in ob.data.layers}
print(json.dumps(out))
"""


def digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def shot(tmp_path):
    """A shot: two layers (one locked), a drawing shared by two keyframes, an empty
    keyframe, and a second Grease Pencil object."""
    clear_scene()
    ob = make_object({1: "house", 5: "cup", 13: None}, name="Shot", layer_name="Ink")
    ob.data.layers["Ink"].frames.copy(5, 9, instance_drawing=True)
    locked = ob.data.layers.new("Locked")
    fill_drawing(locked.frames.new(1).drawing, sample_points("fish"))
    locked.lock = True
    make_object({1: "fish"}, name="Extra", layer_name="Ink")
    path = tmp_path / "shot.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)
    return path


def run(*args, cwd=None):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, cwd=cwd, timeout=600)


def inspect(path) -> dict:
    out = subprocess.run([sys.executable, "-c", INSPECT, str(path)], capture_output=True,
                         text=True, timeout=300)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_batch_writes_a_new_file_and_leaves_the_shot_alone(shot, tmp_path):
    before = digest(shot)
    out, summary = tmp_path / "out.blend", tmp_path / "summary.json"
    done = run(shot, "--output", out, "--summary", summary, "--jobs", "2")
    assert done.returncode == 0, done.stderr
    assert digest(shot) == before
    info = json.loads(summary.read_text())
    assert info["drawings"] == 3  # house, the shared cup once, the fish of Extra
    assert 0 < info["strokes_out"] < info["strokes_in"]
    skipped = " ".join(info["files"][0]["skipped"])
    assert "layer 'Locked' (locked)" in skipped
    layers = inspect(out)
    # the empty keyframe 13 stays empty in the output: the cup of 5 and 9 ends there
    assert sorted(layers["Shot"]["Ink simplified"], key=int) == ["1", "5", "9", "13"]
    assert layers["Shot"]["Ink simplified"]["13"] == 0
    assert layers["Shot"]["Ink simplified"]["5"] == layers["Shot"]["Ink simplified"]["9"] > 0
    assert "Locked simplified" not in layers["Shot"]
    assert layers["Extra"]["Ink simplified"]["1"] > 0
    assert "frame 5,9:" in done.stdout  # progress names the drawing's frames


def test_jobs_and_the_double_dash_convention_agree(shot, tmp_path):
    one = run("--", shot, "--output", tmp_path / "one.blend", "--jobs", "1")
    two = run(shot, "--output", tmp_path / "two.blend", "--jobs", "2")
    assert one.returncode == two.returncode == 0, one.stderr + two.stderr
    assert inspect(tmp_path / "one.blend") == inspect(tmp_path / "two.blend")


def test_frame_range_objects_and_in_place_with_backup(shot):
    before = shot.read_bytes()
    done = run(shot, "--in-place", "--frames", "4-9", "--objects", "Shot")
    assert done.returncode == 0, done.stderr
    assert shot.with_suffix(".blend1").read_bytes() == before
    layers = inspect(shot)
    assert sorted(layers["Shot"]["Ink simplified"]) == ["5", "9"]
    assert "Ink simplified" not in layers["Extra"]


def test_several_files_into_a_folder(shot, tmp_path):
    other = tmp_path / "other.blend"
    other.write_bytes(shot.read_bytes())
    done = run(shot, other, "--output", tmp_path / "out", "--frames", "current")
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["other.blend", "shot.blend"]
    assert "2 file(s)" in done.stdout


def test_several_files_on_a_dask_cluster_match_the_local_run_and_resume_skips_done_files(
        shot, tmp_path, dask_cluster):
    """The client reads every file's drawings with bpy and sends them first; the workers
    (plain Python with the project's package, no Blender) simplify; the files are written
    as on one machine."""
    address, _ = dask_cluster
    other = tmp_path / "other.blend"
    other.write_bytes(shot.read_bytes())
    local = run(shot, other, "--output", tmp_path / "local", "--jobs", "1")
    remote = run(shot, other, "--output", tmp_path / "remote", "--scheduler", address)
    assert local.returncode == remote.returncode == 0, remote.stdout + remote.stderr
    assert remote.stdout.count("drawing(s) sent to") == 2  # both files in flight at once
    for name in ("shot.blend", "other.blend"):
        assert inspect(tmp_path / "remote" / name) == inspect(tmp_path / "local" / name)
    (tmp_path / "remote" / "other.blend").unlink()
    again = run(shot, other, "--output", tmp_path / "remote", "--scheduler", address,
                "--resume")
    assert again.returncode == 0, again.stderr
    assert "shot.blend: done before, skipped" in again.stdout and "1 file(s)" in again.stdout
    assert inspect(tmp_path / "remote" / "other.blend") == inspect(tmp_path / "local" /
                                                                   "other.blend")


def test_errors_exit_2_with_one_line(shot, tmp_path):
    clear_scene()
    bpy.data.objects.new("Mesh", bpy.data.meshes.new("Mesh"))
    empty = tmp_path / "no_gp.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(empty), copy=True)
    for args, message in (([tmp_path / "missing.blend"], "no such file"),
                          ([empty], "no Grease Pencil"),
                          ([shot, "--frames", "9-2"], "bad frame range"),
                          ([shot, "--frames", "x"], "bad frame range")):
        done = run(*args)
        assert done.returncode == 2, (args, done.stdout, done.stderr)
        assert message in done.stderr and done.stderr.count("\n") == 1


def test_core_batch_folder(tmp_path):
    out, summary = tmp_path / "out", tmp_path / "s.json"
    done = subprocess.run([sys.executable, "-m", "core", "batch", str(SAMPLES), str(out),
                           "--jobs", "2", "--summary", str(summary)], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    info = json.loads(summary.read_text())
    assert len(info["files"]) == 4 and info["jobs"] == 2
    assert sorted(p.name for p in out.iterdir()) == ["cup.svg", "fish.scap.svg",
                                                     "fish.svg.svg", "house.svg"]
    bad = subprocess.run([sys.executable, "-m", "core", "batch", str(tmp_path / "none"),
                          str(out)], cwd=ROOT, capture_output=True, text=True)
    assert bad.returncode == 1 and "no such folder" in bad.stderr
