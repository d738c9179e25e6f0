"""What a Dask worker runs: one sketch, given and returned as plain data.

A worker needs the project's Python package (``core``, installed or on its path) and
nothing of Blender. A client holding ``core`` under another name (inside Blender it is a
subpackage of the extension) sends :func:`simplify_by_name` by value: it has no globals and
imports the worker's own ``core.remote`` by that absolute name. What travels is dicts of
numpy arrays, strings and numbers, which unpickle anywhere. Invariant: the strokes and
regions that come back are exactly those of ``simplified(simplify(sketch, params))``.
"""

from __future__ import annotations

from dataclasses import fields

from .engine import simplified
from .params import SimplifyParams
from .simplify import simplify
from .sketch import Sketch, SketchError, Stroke

__all__ = ["plain_stroke", "simplify_by_name", "simplify_payload"]


def plain_stroke(stroke: Stroke) -> dict:
    """A stroke as a dict of its fields, for ``Stroke(**d)`` at the other end."""
    return {f.name: getattr(stroke, f.name) for f in fields(stroke)}


def simplify_by_name(payload: dict) -> dict:
    """:func:`simplify_payload` of the ``core`` package installed where this runs."""
    from core.remote import simplify_payload

    return simplify_payload(payload)


def simplify_payload(payload: dict) -> dict:
    """Simplify ``payload`` = {"strokes": [stroke fields...], "width", "height", "params":
    SimplifyParams fields, "regions": bool}; returns {"strokes", "regions", "width"} or
    {"error": message} (a bad sketch, or any failure, reported rather than raised so that
    one sketch never stops the rest)."""
    try:
        sketch = Sketch([Stroke(**s) for s in payload["strokes"]], payload["width"],
                        payload["height"])
        out = simplified(simplify(sketch, SimplifyParams(**payload["params"])),
                         payload["regions"])
    except SketchError as exc:
        return {"error": str(exc)}
    except Exception as exc:  # noqa: BLE001 - reported by the sketch's name on the client
        return {"error": f"{type(exc).__name__}: {exc}"}
    return {"strokes": [plain_stroke(s) for s in out.strokes],
            "regions": [(r.outline, tuple(r.holes)) for r in out.regions],
            "width": out.width}
