"""The command line, ``python -m core``: simplify one sketch, ``inspect``, ``batch``.
An application of the library, left out of the Blender extension."""

from .main import main

__all__ = ["main"]
