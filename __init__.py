"""SketchSimp, the Blender extension: entry point only.

Installed, this folder is the package ``bl_ext.<repo>.sketchsimp``; ``core`` is its pure
Python subpackage and ``sketchsimp_addon`` its Blender glue. Nothing here imports bpy at
module level, so tests of ``core`` can import the folder without Blender.
"""


def register() -> None:
    from . import sketchsimp_addon

    sketchsimp_addon.register()


def unregister() -> None:
    from . import sketchsimp_addon

    sketchsimp_addon.unregister()
