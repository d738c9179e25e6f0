"""The closed regions of the clean lines, for fills (issue 32 item 3: closed regions come
from the fitted lines, not from the rough ink).

The regions are the white spaces the output lines enclose. A free end is first carried on
along its direction up to ``reach``, to the first line (or other end carried on) it meets,
as Blender's fill tool closes gaps by extending lines: a wall that stops a little short
of the floor, two roof lines that stop short of meeting at the top, still close their
region. Then the lines are thickened by ``close`` (so that two lines that stop within
twice that of each other close a region: the gap a junction leaves), the white space not
reachable from outside the drawing is cut into its connected parts, and each part is grown
back by ``close`` onto the lines' middles (mitred, so that a square region keeps its
corners). A part with ink inside it, touching it nowhere (a face's eyes), has that ink's
outline as a hole. A region lying inside another's outline is a hole of it, filled only
inside a hole in turn: the even-odd rule of vector art (a ring's hole stays empty, a
face's eyes are cut out of it, a pupil inside an eye is filled); regions side by side are
each filled.

Invariants: a region never reaches past the middle of the lines around it (a fill stays
inside the lines); a white space narrower than ``2 * close`` is no region (a sliver
between two passes).
"""

from __future__ import annotations

import numpy as np
import shapely

from ..sketch import Region

__all__ = ["extensions", "line_regions"]


def _ring(r) -> np.ndarray:
    return np.asarray(r.coords)[:-1]


def extensions(lines: list[np.ndarray], closed: list[bool], reach: float,
               touch: float) -> list[np.ndarray]:
    """The segments that carry each free end of ``lines`` on along its direction (taken
    over ``reach`` / 4 of the line) to the first line, or other end carried on, that it
    meets within ``reach``; an end within ``touch`` of another line is not free.

    >>> wall = np.array([[0.0, 0.0], [0.0, 9.0]])  # stops 1 short of the floor
    >>> floor = np.array([[-5.0, 10.0], [5.0, 10.0]])
    >>> [e.round(6).tolist() for e in extensions([wall, floor], [False, False], 2.0, 0.1)]
    [[[0.0, 9.0], [0.0, 10.0]]]
    """
    geoms = [shapely.LineString(p) for p in lines]
    tree = shapely.STRtree(geoms)
    rays, owner = [], []
    for k, (p, c) in enumerate(zip(lines, closed)):
        if c or len(p) < 2:
            continue
        for end, inward in ((p[-1], p[::-1]), (p[0], p)):
            near = tree.query(shapely.Point(end), predicate="dwithin", distance=touch)
            if any(j != k for j in near.tolist()):
                continue  # it meets a line already
            back = inward[np.searchsorted(np.r_[0.0, np.cumsum(np.hypot(*np.diff(
                inward, axis=0).T))], reach / 4, side="left").clip(1, len(inward) - 1)]
            way = end - back
            size = float(np.hypot(*way))
            if not size > 0:
                continue
            rays.append(shapely.LineString([end, end + way / size * reach]))
            owner.append(k)
    if not rays:
        return []
    out = []
    ray_tree = shapely.STRtree(rays)
    for r, (ray, k) in enumerate(zip(rays, owner)):
        hits = [shapely.intersection(ray, geoms[j]) for j in
                tree.query(ray, predicate="intersects").tolist() if j != k]
        hits += [shapely.intersection(ray, rays[j]) for j in
                 ray_tree.query(ray, predicate="intersects").tolist() if j != r]
        at = [shapely.line_locate_point(ray, q) for h in hits
              for q in shapely.get_parts(shapely.extract_unique_points(h))]
        at = [a for a in at if a > 0]
        if at:  # the segment from the end to the first it meets
            start = np.asarray(ray.coords[0])
            out.append(np.array([start, shapely.get_coordinates(
                shapely.line_interpolate_point(ray, min(at)))[0]]))
    return out


def line_regions(lines: list[np.ndarray], closed: list[bool], close: float,
                 smallest: float, reach: float = 0.0) -> list[Region]:
    """The regions to fill that ``lines`` enclose (see the module), largest first.

    Args:
        lines: (n, 2) polylines.
        closed: whether each line is closed (its last point joins its first).
        close: half the widest gap between two lines' ends that still closes a region.
        smallest: regions of less area are slivers, left out (and so are holes).
        reach: how far a free end is carried on to close a region (:func:`extensions`).

    Returns:
        The regions to fill, each an outline and its holes.

    >>> square = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    >>> [r] = line_regions([square], [True], 0.5, 1.0)
    >>> float(shapely.Polygon(r.outline).area), r.holes
    (100.0, ())
    >>> open_square = np.array([[0.0, 0.4], [0, 10], [10, 10], [10, 0], [0, 0]])
    >>> len(line_regions([open_square], [False], 0.5, 1.0))  # a gap of 0.4 closes
    1
    >>> len(line_regions([open_square], [False], 0.1, 1.0))
    0
    """
    keep = [k for k, p in enumerate(lines) if len(p) >= 2]
    if not keep or not close > 0:
        return []
    lines = [np.vstack([lines[k], lines[k][:1]]) if closed[k] and len(lines[k]) > 2
             else lines[k] for k in keep]
    closed = [closed[k] for k in keep]
    if reach > 0:
        lines = lines + extensions(lines, closed, reach, close)
    geoms = [shapely.LineString(p) for p in lines]
    ink = shapely.union_all(shapely.buffer(np.array(geoms), close, quad_segs=4))
    x0, y0, x1, y1 = ink.bounds
    frame = shapely.box(x0 - close, y0 - close, x1 + close, y1 + close)
    white = [part for part in shapely.get_parts(shapely.difference(frame, ink))
             if not part.exterior.intersects(frame.exterior)]  # the outside is no region
    parts = []
    for part in white:
        grown = shapely.buffer(part, close, join_style="mitre", mitre_limit=4.0)
        for piece in shapely.get_parts(grown):
            if piece.area >= smallest:
                parts.append(piece)
    if not parts:
        return []
    outlines = np.array([shapely.Polygon(part.exterior) for part in parts])
    inside, around = shapely.STRtree(outlines).query(
        shapely.point_on_surface(np.array(parts)), predicate="within")
    depth = np.bincount(inside[inside != around], minlength=len(parts))
    parts = sorted((part for part, d in zip(parts, depth.tolist()) if d % 2 == 0),
                   key=lambda part: -part.area)
    return [Region(_ring(part.exterior), tuple(_ring(h) for h in part.interiors
                                                if shapely.Polygon(h).area >= smallest))
            for part in parts]
