"""A real Dask cluster for tests: a scheduler and two workers on 127.0.0.1, started as Dask
ships them (the ``dask`` command beside this Python), killed at the end."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from helpers import ROOT

__all__ = ["ENV", "dask_cluster"]

DASK = Path(sys.executable).parent / "dask"
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}  # workers need core, nothing of Blender


def _start(args: list[str], log: Path) -> subprocess.Popen:
    return subprocess.Popen([str(DASK), *args], stdout=log.open("w"), stderr=subprocess.STDOUT,
                            env=ENV, cwd=ROOT, start_new_session=True)


@pytest.fixture
def dask_cluster(tmp_path):
    """(scheduler address, the two worker processes: one worker each, one thread)."""
    distributed = pytest.importorskip("distributed")
    file = tmp_path / "scheduler.json"
    procs = [_start(["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                     "--scheduler-file", str(file)], tmp_path / "scheduler.log")]
    try:
        for _ in range(300):
            if file.exists() and file.stat().st_size:
                break
            time.sleep(0.1)
        address = json.loads(file.read_text())["address"]
        workers = [_start(["worker", "--scheduler-file", str(file), "--nthreads", "1",
                           "--no-nanny", "--no-dashboard", "--name", f"w{k}"],
                          tmp_path / f"worker{k}.log") for k in range(2)]
        procs += workers
        with distributed.Client(address, timeout=30) as client:
            client.wait_for_workers(2, timeout=60)
        yield address, workers
    finally:
        for p in procs:  # nothing of theirs to keep
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=30)


