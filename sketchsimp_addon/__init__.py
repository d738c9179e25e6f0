"""Blender glue: reads Grease Pencil / curve strokes into plain numpy data, runs ``core``,
writes the result back. Its operator and panel are tracked as their own issue; until they
land, registering the extension adds nothing to Blender's interface."""

CLASSES: tuple[type, ...] = ()


def register() -> None:
    import bpy

    for cls in CLASSES:
        bpy.utils.register_class(cls)


def unregister() -> None:
    import bpy

    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
