"""Run the test suite inside Blender, or with the bpy wheel.

    blender -b --python scripts/run_tests.py -- [pytest args]
    python scripts/run_tests.py [pytest args]

Under Blender the script directory is not on sys.path and arguments after ``--`` are ours;
with the wheel, ``sys.argv`` holds them directly. The exit status is pytest's.
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def script_args(argv: list[str]) -> list[str]:
    if "--" in argv:
        return argv[argv.index("--") + 1:]
    import bpy

    return argv[1:] if bpy.app.binary_path == "" else []


def main() -> int:
    home = tempfile.mkdtemp(prefix="sketchsimp-tests-")
    os.environ.setdefault("BLENDER_USER_RESOURCES", os.path.join(home, "user"))
    os.environ.setdefault("XDG_CACHE_HOME", os.path.join(home, "cache"))
    os.chdir(ROOT)
    sys.path.insert(0, str(ROOT))
    import pytest

    return int(pytest.main(script_args(sys.argv) or ["tests"]))


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    # under Blender an uncaught failure would still exit 0: leave with pytest's status
    os._exit(code)
