"""Batch simplification: scripts/batch_simplify.py on .blend files, python -m core batch."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
from pathlib import Path

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
    assert "layer 'Locked' (locked: unlock it" in skipped
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
    out, ink = layers["Shot"]["Ink simplified"], layers["Shot"]["Ink"]
    # the source is hidden: keyframes outside 4-9 are shown on the result as drawn
    assert sorted(out, key=int) == ["1", "5", "9", "13"]
    assert out["1"] == ink["1"] and out["13"] == ink["13"] == 0
    assert 0 < out["5"] == out["9"] < ink["5"]
    assert "Ink simplified" not in layers["Extra"]


def test_several_files_into_a_folder(shot, tmp_path):
    other = tmp_path / "other.blend"
    other.write_bytes(shot.read_bytes())
    done = run(shot, other, "--output", tmp_path / "out", "--frames", "current")
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["other.blend", "shot.blend"]
    assert "2 file(s)" in done.stdout


def test_a_folder_of_blend_files_is_every_file_in_it(shot, tmp_path):
    """A folder given is its .blend files (not an earlier run's *_simplified.blend); an
    empty folder is named, not called a missing file."""
    folder = tmp_path / "shots"
    folder.mkdir()
    for name in ("a.blend", "b.blend", "a_simplified.blend"):
        (folder / name).write_bytes(shot.read_bytes())
    done = run(folder, "--output", tmp_path / "out", "--frames", "current")
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["a.blend", "b.blend"]
    (tmp_path / "empty").mkdir()
    empty = run(tmp_path / "empty", "--output", tmp_path / "out2")
    assert empty.returncode == 2 and "no .blend file in" in empty.stderr


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


def test_bad_options_exit_2_with_one_line_before_any_work(shot, tmp_path):
    unwritable = tmp_path / "a_file"
    unwritable.write_text("not a folder")
    for args, message in (([shot, "--frames", "9-2"], "bad frame range"),
                          ([shot, "--frames", "x"], "bad frame range"),
                          ([shot, "--jobs", "0"], "--jobs must be at least 1"),
                          ([shot, shot, "--output", unwritable / "out"],
                           "output folder"),
                          ([shot, "--output", "/proc/sketchsimp/out.blend"],
                           "output folder"),
                          ([shot, "--summary", unwritable / "s.json"], "summary folder"),
                          ([shot, "--summary", tmp_path], "is a folder")):
        done = run(*args, *([] if "--frames" in args else ["--frames", "current"]))
        assert done.returncode == 2, (args, done.stdout, done.stderr)
        assert message in done.stderr and done.stderr.count("\n") == 1, done.stderr
        assert "drawing(s)" not in done.stdout  # nothing was simplified
    assert not (tmp_path / "shot_simplified.blend").exists()


def test_a_corrupt_an_empty_and_a_file_without_grease_pencil_are_named_and_the_rest_done(
        shot, tmp_path):
    clear_scene()
    bpy.data.objects.new("Mesh", bpy.data.meshes.new("Mesh"))
    no_gp = tmp_path / "no_gp.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(no_gp), copy=True)
    corrupt = tmp_path / "corrupt.blend"
    corrupt.write_bytes(b"BLENDER-v405" + bytes(range(256)) * 8)
    empty = tmp_path / "empty.blend"
    empty.write_bytes(b"")
    other = tmp_path / "other.blend"
    other.write_bytes(shot.read_bytes())
    out, summary = tmp_path / "out", tmp_path / "summary.json"
    done = run(corrupt, shot, empty, tmp_path / "missing.blend", no_gp, other,
               "--output", out, "--summary", summary, "--frames", "current")
    assert done.returncode == 1, done.stdout + done.stderr
    assert sorted(p.name for p in out.iterdir()) == ["other.blend", "shot.blend"]
    info = json.loads(summary.read_text())
    reasons = {Path(f["file"]).name: f["reason"] for f in info["failed"]}
    assert sorted(reasons) == ["corrupt.blend", "empty.blend", "missing.blend", "no_gp.blend"]
    assert "not a readable .blend" in reasons["corrupt.blend"]
    assert "empty file" in reasons["empty.blend"]
    assert "no such file" in reasons["missing.blend"]
    assert "no Grease Pencil" in reasons["no_gp.blend"]
    assert [Path(r["file"]).name for r in info["files"]] == ["shot.blend", "other.blend"]
    assert "4 file(s) failed" in done.stdout
    for name in reasons:
        assert name in done.stderr


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
