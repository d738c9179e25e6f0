"""Run in a fresh interpreter by test_extension_package: install the built zip into the bpy
module, enable it, and simplify a sample through the installed copy. Prints JSON."""

import importlib
import json
import sys
from pathlib import Path

import bpy

addon_utils = importlib.import_module("addon_utils")  # on sys.path once bpy is imported

zip_path, sample_root = sys.argv[1], sys.argv[2]
sys.path[:0] = [sample_root, str(Path(sample_root).parent / "scripts")]  # scene helpers
bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                         enable_on_install=True)
name = "bl_ext.user_default.sketchsimp"
module = sys.modules.get(name)
enabled = addon_utils.check(name)
from blender_scene import make_object  # noqa: E402  (needs bpy, after the install)

# five keyframes: the installed copy runs them in a process pool, whose workers must
# rebuild the bl_ext.user_default.sketchsimp package to find core
ob = make_object({1: "house", 5: "cup", 9: "fish", 13: "house", 17: "cup"})
result = bpy.ops.sketchsimp.simplify(scope="ALL")
out_layer = ob.data.layers.get("Lines simplified")
site = Path(bpy.utils.user_resource("EXTENSIONS", path=".local"))
wheels = sorted(p.name for p in site.glob("lib/python3*/site-packages/*.dist-info"))

print(json.dumps({
    "module": module.__file__ if module else None, "enabled": list(enabled),
    "result": sorted(result), "frames_out": len(out_layer.frames) if out_layer else 0,
    "strokes_out": out_layer.frames[0].drawing.attributes.domain_size(
        "CURVE") if out_layer else 0,
    "wheels": wheels,
}))
addon_utils.disable(name, default_set=True)  # nothing registered at exit (4.5 would hang)
