"""The batch on a real Dask cluster: a scheduler and two workers on 127.0.0.1, started
here as Dask ships them (the ``dask`` command), one of them killed during the run."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from bench_simplify import synthetic
from dask_cluster import ENV
from helpers import ROOT

from core import SimplifyParams, Sketch, Stroke, simplify_all, write_sketch

pytest.importorskip("distributed")


@pytest.fixture
def sketches(tmp_path) -> Path:
    """Ten synthetic rough sketches of 60 to 168 strokes, one drawn twice, and one that
    cannot be simplified (every stroke a single point)."""
    folder = tmp_path / "in"
    folder.mkdir()
    for k in range(10):
        write_sketch(Sketch([Stroke(p) for p in synthetic(60 + 12 * k, seed=k)]),
                     folder / f"s{k:02d}.scap")
    (folder / "s10_again.scap").write_bytes((folder / "s05.scap").read_bytes())
    (folder / "dots.scap").write_text("#100 100\n@1\n{\n\t#0 0\n\t5 5 0\n}\n")
    return folder


def _batch(*args: str) -> subprocess.Popen:
    """``python -m core batch ARGS`` started, its output read as it comes."""
    return subprocess.Popen([sys.executable, "-m", "core", "batch", *args], cwd=ROOT, env=ENV,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def _batch_run(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    """``python -m core batch ARGS`` run to its end."""
    return subprocess.run([sys.executable, "-m", "core", "batch", *args], cwd=ROOT, env=ENV,
                          capture_output=True, text=True, timeout=timeout)


def test_a_batch_on_a_cluster_survives_a_worker_killed_mid_run_and_matches_the_local_run(
        dask_cluster, sketches, tmp_path):
    address, workers = dask_cluster
    local = _batch_run(str(sketches), str(tmp_path / "local"), "--jobs", "1")
    run = _batch(str(sketches), str(tmp_path / "remote"), "--scheduler", address,
                 "--summary", str(tmp_path / "summary.json"))
    lines = [run.stdout.readline()]  # the first sketch finished: the others are in flight
    os.killpg(workers[0].pid, signal.SIGKILL)
    rest, _ = run.communicate(timeout=300)
    lines += rest.splitlines()
    assert run.returncode == 1, lines  # dots.scap failed, and only that
    assert any("failed dots.scap" in line for line in lines), lines
    assert "11 of 12 sketches" in "\n".join(lines)
    assert workers[0].wait(timeout=10) == -signal.SIGKILL
    # 11 distinct sketches computed (the copy once with its original), a line as each ends
    progress = [line.split()[0] for line in lines if line.startswith("  ") and "/" in line]
    assert progress == [f"{k}/11" for k in range(1, 12)], lines
    names = sorted(p.name for p in (tmp_path / "local").iterdir())
    assert names == sorted(p.name for p in (tmp_path / "remote").iterdir())
    assert len(names) == 11 and not any(n.startswith(".partial") for n in names)
    for name in names:
        assert (tmp_path / "remote" / name).read_bytes() == (tmp_path / "local" / name).read_bytes()
    assert local.returncode == 1 and "failed dots.scap" in local.stdout


def test_resume_after_an_interrupted_run_redoes_only_what_is_missing(dask_cluster, sketches,
                                                                    tmp_path):
    address, _ = dask_cluster
    out = tmp_path / "out"
    first = _batch_run(str(sketches), str(out), "--scheduler", address)
    assert first.returncode == 1, first.stdout  # dots.scap
    for name in ("s03.svg", "s07.svg"):  # as if the run had been stopped before them
        (out / name).unlink()
    (out / ".partial-123-s07.svg").write_text("<svg")  # a write cut short
    before = {p.name: p.stat().st_mtime_ns for p in out.glob("s*.svg")}
    again = _batch_run(str(sketches), str(out), "--scheduler", address, "--resume",
                       "--summary", str(tmp_path / "s.json"))
    rows = json.loads((tmp_path / "s.json").read_text())["files"]
    redone = sorted(k for k, v in rows.items() if "strokes_out" in v)
    assert redone == ["s03.scap", "s07.scap"], again.stdout
    assert sum("resumed" in v for v in rows.values()) == 9
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir() if p.name in before} == before
    assert not list(out.glob(".partial-*"))
    assert (out / "s03.svg").exists() and (out / "s07.svg").exists()


def test_a_scheduler_that_does_not_answer_is_one_clear_error(sketches, tmp_path):
    done = _batch_run(str(sketches), str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:9",
                      "--connect-timeout", "2", timeout=120)
    assert done.returncode == 1
    assert "no Dask scheduler answers at tcp://127.0.0.1:9" in done.stderr + done.stdout
    assert not list((tmp_path / "out").glob("*.svg"))


def test_identical_sketches_are_simplified_once_in_the_local_pool():
    t = np.linspace(0, 1, 30)[:, None]
    a = Sketch([Stroke(np.hstack([t, t * 0.2])), Stroke(np.hstack([t, t * 0.2 + 0.01]))])
    b = Sketch([Stroke(np.hstack([t, 1 - t]))])
    calls = []
    outs = simplify_all([a, b, Sketch(list(a.strokes)), a], SimplifyParams(), jobs=2,
                        progress=lambda done, total, k: calls.append((done, total, k)))
    assert calls == [(1, 2, 0), (2, 2, 1)]
    assert [len(o.strokes) for o in outs] == [1, 1, 1, 1]
    assert outs[0] is outs[2] is outs[3]


def test_without_dask_a_scheduler_asks_for_the_cluster_extra(monkeypatch):
    from core import SketchError
    from core.cluster import ClusterRun

    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed
    with pytest.raises(SketchError, match=r"pip install 'sketchsimp\[cluster\]'"):
        ClusterRun("tcp://127.0.0.1:9", SimplifyParams())
