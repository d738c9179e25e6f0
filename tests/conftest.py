"""Keep Blender's user files out of the home directory when tests import bpy."""

import os
import tempfile

_blender_home = tempfile.mkdtemp(prefix="sketchsimp-blender-")
os.environ.setdefault("BLENDER_USER_RESOURCES", os.path.join(_blender_home, "user"))
os.environ.setdefault("XDG_CACHE_HOME", os.path.join(_blender_home, "cache"))

# the dask_cluster fixture: a real scheduler and two workers (tests/dask_cluster.py)
pytest_plugins = ["dask_cluster"]
