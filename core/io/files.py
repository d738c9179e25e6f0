"""Reading and writing sketch files by their suffix (``.svg`` or ``.scap``)."""

from __future__ import annotations

from pathlib import Path

from ..sketch import Sketch, SketchError
from .scap import read_scap, write_scap
from .svg import read_svg, write_svg

__all__ = ["READERS", "WRITERS", "read_sketch", "write_sketch"]

READERS = {".svg": read_svg, ".scap": read_scap}
WRITERS = {".svg": write_svg, ".scap": write_scap}


def read_sketch(path: str | Path) -> Sketch:
    """Read an ``.svg`` or ``.scap`` file; :class:`SketchError` for anything unreadable."""
    path = Path(path)
    reader = READERS.get(path.suffix.lower())
    if reader is None:
        raise SketchError(f"{path}: unknown sketch format {path.suffix!r} (use .svg or .scap)")
    if not path.is_file():
        raise SketchError(f"{path}: no such file")
    try:
        return reader(path)
    except OSError as exc:
        raise SketchError(f"{path}: cannot read ({exc.strerror or exc})") from None


def write_sketch(sketch: Sketch, path: str | Path) -> None:
    """Write an ``.svg`` or ``.scap`` file, chosen by the suffix."""
    path = Path(path)
    writer = WRITERS.get(path.suffix.lower())
    if writer is None:
        raise SketchError(f"{path}: unknown sketch format {path.suffix!r} (use .svg or .scap)")
    writer(sketch, path)
