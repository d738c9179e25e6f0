"""What a Dask worker runs: one sketch, given and returned as plain data.

A worker needs the project's Python package (``core``, installed or on its path) and
nothing of Blender. A client holding ``core`` under another name (inside Blender it is a
subpackage of the extension) sends :func:`simplify_by_name` by value: it has no globals and
imports the worker's own ``core`` by that absolute name. What travels is dicts of numpy
arrays, strings and numbers, which unpickle anywhere. Invariant: the strokes and regions
that come back are exactly those of ``core.simplified(core.simplify(sketch, params))``.
"""

from __future__ import annotations

__all__ = ["simplify_by_name", "simplify_payload"]

#: the fields of a stroke that travel (``core.sketch.Stroke``'s)
STROKE_FIELDS = ("points", "width", "pressure", "style", "source_id", "cluster", "bezier",
                 "closed", "sources")


def simplify_by_name(payload: dict) -> dict:
    """:func:`simplify_payload` of the ``core`` package installed where this runs."""
    from core.remote import simplify_payload

    return simplify_payload(payload)


def simplify_payload(payload: dict) -> dict:
    """Simplify ``payload`` = {"strokes": [stroke fields...], "width", "height", "params":
    SimplifyParams fields, "regions": bool}; returns {"strokes", "regions", "width"} or
    {"error": message} (a bad sketch, or any failure, reported rather than raised so that
    one sketch never stops the rest)."""
    from core import SimplifyParams, Sketch, SketchError, Stroke, simplified, simplify

    try:
        sketch = Sketch([Stroke(**s) for s in payload["strokes"]], payload["width"],
                        payload["height"])
        out = simplified(simplify(sketch, SimplifyParams(**payload["params"])),
                         payload["regions"])
    except SketchError as exc:
        return {"error": str(exc)}
    except Exception as exc:  # noqa: BLE001 - reported by the sketch's name on the client
        return {"error": f"{type(exc).__name__}: {exc}"}
    return {"strokes": [{k: getattr(s, k) for k in STROKE_FIELDS} for s in out.strokes],
            "regions": [(r.outline, tuple(r.holes)) for r in out.regions],
            "width": out.width}
