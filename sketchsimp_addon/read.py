"""Reading: which layers, keyframes and strokes a run takes, read into sketches for the
core (:func:`gather_drawings`); what it leaves alone goes to the report with the reason."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .convert import (
    drawing_plane,
    far_out,
    to_sketch,
)
from .gp_io import read_drawing
from .records import Prepared, RunReport

__all__ = [
    "collect_drawings", "FLAT", "gather_drawings", "Gathered", "result_of", "RESULT_SUFFIXES",
    "source_frames", "target_layers", "untouchable_materials", "why_left_alone",
]


#: the names a result layer gets after its source's
RESULT_SUFFIXES = (" simplified", " fills")


def why_left_alone(layer) -> str | None:
    """Why a layer may not be simplified: locked or hidden, itself or in a layer group
    (a locked group locks its layers, a hidden one hides them); None when it may."""
    if layer.lock or layer.hide:
        return "locked" if layer.lock else "hidden"
    group = layer.parent_group
    while group is not None:
        if group.lock or group.hide:
            return f"in {'locked' if group.lock else 'hidden'} group '{group.name}'"
        group = group.parent_group
    return None


def result_of(gp, layer):
    """The layer whose result (" simplified", " fills") ``layer`` is, beside it, or None."""
    for suffix in RESULT_SUFFIXES:
        if layer.name.endswith(suffix):
            source = gp.layers.get(layer.name[:-len(suffix)])
            if source is not None and source.parent_group == layer.parent_group:
                return source
    return None


def target_layers(gp, which: str, report: RunReport) -> list:
    """The layers to work on; locked and hidden ones (or in such groups) are left alone
    and named."""
    candidates = [gp.layers.active] if which == "ACTIVE" else list(gp.layers)
    out = []
    for layer in candidates:
        if layer is None:
            continue
        why = why_left_alone(layer)
        source = result_of(gp, layer)
        if source is not None and source in candidates and why_left_alone(source) is None:
            report.rewritten.append(layer.name)  # its source's run writes it again
            continue
        if source is not None:
            why = (f"the result of '{source.name}': replaced when '{source.name}' is "
                   "simplified again")
        if why == "hidden" and gp.layers.get(f"{layer.name} simplified") is not None:
            why = (f"hidden: simplified before into '{layer.name} simplified'; show it to "
                   "simplify it again")
        if why in ("locked", "hidden"):  # what to do about it, in Blender's terms
            why += (": unlock it (its lock icon in the Layers list) to simplify it"
                    if why == "locked" else ": show it (its eye icon) to simplify it")
        if why is None:
            out.append(layer)
        else:
            report.skipped.append(f"layer '{layer.name}' ({why})")
    return out


def untouchable_materials(obj) -> set[int]:
    """Material slots whose strokes are left alone: hidden or locked Grease Pencil
    materials (the artist has put those strokes out of reach)."""
    out = set()
    for k, mat in enumerate(obj.data.materials):
        style = getattr(mat, "grease_pencil", None) if mat is not None else None
        if style is not None and (style.hide or style.lock):
            out.add(k)
    return out


def source_frames(layer, scope: str, frame_number: int,
                  frame_range: tuple[int, int] | None = None) -> list:
    """The keyframes to simplify: the one shown at ``frame_number``; every one ("ALL",
    within ``frame_range`` when given); or those shown in ``frame_range`` ("RANGE": its
    keyframes and the one showing at its start, drawn before it)."""
    if scope == "ALL" and frame_range is None:
        return list(layer.frames)
    if scope in ("ALL", "RANGE") and frame_range is not None:
        lo, hi = frame_range
        showing = layer.get_frame_at(lo) if scope == "RANGE" else None
        first = showing.frame_number if showing is not None else lo
        return [f for f in layer.frames if first <= f.frame_number <= hi]
    frame = layer.get_frame_at(frame_number)
    return [frame] if frame is not None else []


#: a drawing whose points lie farther than this share of its size from its plane is not
#: flat: it is still flattened (the core works in 2D), and the report says by how much
FLAT = 0.02
def collect_drawings(obj, options, frame_number: int, report: RunReport,
                     frame_range: tuple[int, int] | None = None) -> list[tuple]:
    """(layer, frames) for each distinct drawing to simplify: a drawing shared by several
    keyframes is listed once, with all of them. ``frame_range`` narrows "ALL" scope."""
    drawings: dict[int, tuple] = {}
    for layer in target_layers(obj.data, options.layers, report):
        for frame in source_frames(layer, options.scope, frame_number, frame_range):
            key = frame.drawing.as_pointer()
            if key in drawings:
                drawings[key][1].append(frame)
            else:
                drawings[key] = (layer, [frame])
    return list(drawings.values())


@dataclass
class Gathered:
    """The drawings of one object read for a run: what to simplify, the keyframes drawn
    empty (kept empty in the output when it has others), and how many strokes of hidden or
    locked materials were left alone."""

    prepared: list[Prepared]
    empty: list[tuple]
    held: int


def gather_drawings(obj, options, frame_number: int, report: RunReport,
                    frame_range: tuple[int, int] | None = None) -> Gathered:
    """Read the chosen drawings of a Grease Pencil object into sketches; what cannot be
    simplified goes to ``report``."""
    prepared = []
    empty = []  # keyframes drawn empty: kept empty in the output when it has others
    untouchable = untouchable_materials(obj)
    held = 0  # strokes of hidden or locked materials, left as they are
    for layer, frames in collect_drawings(obj, options, frame_number, report, frame_range):
        data = read_drawing(frames[0].drawing)
        where = f"'{layer.name}' frame {frames[0].frame_number}"
        if data.num_strokes == 0:
            if options.scope in ("ALL", "RANGE"):
                empty.append((layer, frames))
            else:
                report.skipped.append(f"an empty keyframe on {where}")
            continue
        usable = [k for k in range(data.num_strokes)
                  if (options.scope != "SELECTED" or data.selected[k])
                  and data.offsets[k + 1] - data.offsets[k] >= 2]
        chosen = [k for k in usable if int(data.material_index[k]) not in untouchable]
        held += len(usable) - len(chosen)
        if usable and not chosen:
            report.skipped.append(f"only strokes of hidden or locked materials on {where}")
            continue
        if not chosen:
            report.skipped.append(
                f"no stroke selected on {where}" if options.scope == "SELECTED"
                and not data.selected.any() else f"only strokes of one point on {where}")
            continue
        broken = far_out(data.positions)
        if broken.any():  # left out as a NaN is: the core drops them
            report.notes.append(f"{int(broken.sum())} point(s) far outside the drawing on "
                                f"{where} left out")
            data.positions = data.positions.copy()
            data.positions[broken] = np.nan
        points = data.positions[np.concatenate([np.arange(data.offsets[k], data.offsets[k + 1])
                                                for k in chosen])]
        if np.isfinite(points).all(axis=1).sum() < 2:  # drawing_plane leaves NaN points out
            report.skipped.append(f"a drawing without finite points on {where}")
            continue
        plane = drawing_plane(points)
        off = plane.off_plane(points)
        size = float(np.hypot(*np.ptp(plane.to_2d(points[np.isfinite(points).all(axis=1)]),
                                      axis=0)))
        if size > 0 and off > FLAT * size:
            report.notes.append(f"the drawing on {where} is not flat: points up to {off:.3g} "
                                f"off its plane ({100 * off / size:.0f}% of its size) were "
                                "flattened onto it")
        prepared.append(Prepared(layer, frames, data, chosen, plane,
                                 to_sketch(data, chosen, plane)))
    return Gathered(prepared, empty, held)
