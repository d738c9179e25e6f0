"""``python -m core inspect`` and the real sketches of ../shared/data."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from helpers import ROOT, SAMPLES, require_data

from core.cli import main
from core.cli.inspection import inspect_sketch


def test_inspect_prints_counts(capsys):
    assert main(["inspect", str(SAMPLES / "house.scap")]) == 0
    out = capsys.readouterr().out
    for word in ("strokes", "nodes", "curves", "patches", "components", "seconds"):
        assert word in out


def test_inspect_json_matches_the_complex(capsys):
    assert main(["inspect", str(SAMPLES / "cup.scap"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info == {**info, **{k: v for k, v in inspect_sketch(SAMPLES / "cup.scap").items()
                               if k not in ("seconds", "read_seconds")}}
    assert info["nodes"] - info["curves"] + info["patches"] == info["components"]
    assert info["clusters"] == 5


def test_inspect_errors_exit_non_zero_with_one_line(tmp_path):
    bad = tmp_path / "bad.scap"
    bad.write_text("{\n1 2 0\n")
    for args in (["inspect", str(tmp_path / "missing.scap")], ["inspect", str(bad)]):
        run = subprocess.run([sys.executable, "-m", "core", *args], cwd=ROOT,
                             capture_output=True, text=True)
        assert run.returncode == 1
        assert run.stderr.count("\n") == 1 and run.stderr.startswith("python -m core:")


@pytest.mark.data
def test_every_real_sketch_builds_a_valid_complex():
    files = require_data()
    for path in files:
        info = inspect_sketch(path)  # raises if Euler's formula fails
        assert info["nodes"] - info["curves"] + info["patches"] == info["components"], path
        assert info["curves"] > 0


def test_the_local_pool_and_the_dask_runner_share_only_core_engine():
    """core.cluster and core.remote never import core.parallel (the pool), and
    core.engine, the interface both use, imports neither: no import circle."""
    import ast

    def imported(name: str) -> set[str]:
        tree = ast.parse((ROOT / "core" / f"{name}.py").read_text())
        return {node.module for node in ast.walk(tree)
                if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module}

    assert "parallel" not in imported("cluster") | imported("remote")
    assert "engine" in imported("cluster") and "engine" in imported("remote")
    assert not {"parallel", "cluster", "remote"} & imported("engine")
