"""Noding strokes with GEOS: every crossing, overlap and self-intersection becomes a vertex.

The strokes are unioned with snap-rounding on a fixed grid (OverlayNG through shapely 2),
which splits them at every intersection and dissolves collinear overlaps into one piece;
the pieces are then merged through vertices of degree 2, so that each result runs between
two nodes of degree other than 2 (or is a closed loop).
"""

from __future__ import annotations

import numpy as np
import shapely

from ..arrays.geometry import lines_from, split_coordinates

__all__ = ["GRID", "more_crossings_than", "node_strokes"]

#: snapping grid in the unit-diagonal frame: 1e-6 of the bounding-box diagonal
GRID = 1e-6


def node_strokes(strokes: list[np.ndarray], grid: float = GRID) -> list[np.ndarray]:
    """Polylines between nodes: the noded, dissolved, degree-2-merged strokes.

    Coordinates come back snapped to ``grid``; closed loops repeat their first point last.
    """
    lines = lines_from(strokes)
    # GEOS can raise the CPU's divide-by-zero flag inside snap-rounding on degenerate
    # segments, which numpy reports as a warning; the output is checked below instead
    with np.errstate(divide="ignore", invalid="ignore"):
        union = shapely.unary_union(lines, grid_size=grid)
    merged = shapely.get_parts(shapely.line_merge(union))
    merged = merged[shapely.get_type_id(merged) == 1]  # LineString only
    merged = merged[shapely.length(merged) > 0]
    curves = split_coordinates(merged)
    if curves and not all(np.isfinite(c).all() for c in curves):
        raise ArithmeticError("noding produced non-finite coordinates")
    return curves


def more_crossings_than(strokes: list[np.ndarray], limit: int) -> int | None:
    """The number of proper crossings between the strokes' segments if it exceeds
    ``limit`` (counted up to the first chunk past it), else None.

    Noding time and memory grow with the crossings, not the points: a 20,000-point stroke
    that shakes across itself crosses itself millions of times. Counting them with a
    spatial index, a chunk of segments at a time (small at first, in case each already
    crosses thousands), is quick and stops early."""
    segments = [np.stack([s[:-1], s[1:]], axis=1) for s in strokes if len(s) >= 2]
    if not segments:
        return None
    geoms = shapely.linestrings(np.concatenate(segments))
    # a segment and the next one of its stroke share a point and never cross: left out
    first = np.zeros(len(geoms), dtype=bool)
    first[np.cumsum([0] + [len(s) for s in segments[:-1]])] = True
    tree = shapely.STRtree(geoms)
    # segments whose boxes overlap bound the crossings from above and cost a fraction of
    # the exact test: most sketches stop here
    if _count_pairs(tree, geoms, first, limit, None) is None:
        return None
    return _count_pairs(tree, geoms, first, limit, "crosses")


def _count_pairs(tree: shapely.STRtree, geoms: np.ndarray, first: np.ndarray, limit: int,
                 predicate: str | None) -> int | None:
    """Pairs of ``geoms`` meeting ``predicate`` (boxes overlapping if None), but for a
    segment and the next of its stroke (``first`` marks each stroke's first segment),
    counted a growing chunk at a time up to the first chunk past ``limit``; None if
    within it."""
    count, start, chunk = 0, 0, 256
    while start < len(geoms):
        i, j = tree.query(geoms[start:start + chunk], predicate=predicate)
        i = i + start
        count += int(((i < j) & ~((j == i + 1) & ~first[j])).sum())
        if count > limit:
            return count
        start, chunk = start + chunk, min(2 * chunk, 16384)
    return None
