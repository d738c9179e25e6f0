"""Loading the repository as the Blender extension package, the way Blender does."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def load_extension(name: str = "sketchsimp"):
    """Import the repository root as the package ``name`` (``core``, ``sketchsimp_addon``
    and the root ``__init__`` with register/unregister), without registering anything."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(
        name, ROOT / "__init__.py", submodule_search_locations=[str(ROOT)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module
