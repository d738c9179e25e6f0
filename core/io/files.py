"""Reading and writing sketch files by their suffix (``.svg`` or ``.scap``)."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from pathlib import Path

from ..sketch import Sketch, SketchError

__all__ = ["FORMATS", "read_sketch", "write_sketch"]

#: suffix: the module of this package that reads and writes it, its reader and its writer.
#: A module is imported on first use: SVG needs svgelements and defusedxml, which the
#: Blender add-on (it reads no files) neither needs nor loads
FORMATS = {".svg": ("svg", "read_svg", "write_svg"),
           ".scap": ("scap", "read_scap", "write_scap")}


def _handler(path: Path, which: int) -> Callable:
    """The reader (1) or the writer (2) for the file's suffix."""
    found = FORMATS.get(path.suffix.lower())
    if found is None:
        raise SketchError(f"{path}: unknown sketch format {path.suffix!r} (use .svg or .scap)")
    try:
        module = importlib.import_module(f".{found[0]}", __package__)
    except ImportError as exc:  # the Blender extension ships no SVG reader
        raise SketchError(f"{path}: reading and writing {path.suffix} needs {exc.name} "
                          f"(pip install svgelements defusedxml)") from None
    return getattr(module, found[which])


def read_sketch(path: str | Path) -> Sketch:
    """Read an ``.svg`` or ``.scap`` file; :class:`SketchError` for anything unreadable."""
    path = Path(path)
    reader = _handler(path, 1)
    if not path.is_file():
        raise SketchError(f"{path}: no such file")
    try:
        return reader(path)
    except OSError as exc:
        raise SketchError(f"{path}: cannot read ({exc.strerror or exc})") from None


def write_sketch(sketch: Sketch, path: str | Path) -> None:
    """Write an ``.svg`` or ``.scap`` file, chosen by the suffix."""
    _handler(Path(path), 2)(sketch, Path(path))
