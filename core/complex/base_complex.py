"""The base complex of a sketch (paper section 3.1): nodes, curves and patches.

* nodes: stroke intersections, self-intersections and stroke endpoints; a lone closed loop
  gets one auxiliary node (the paper's second type of vertex);
* curves: maximal polylines between nodes of degree other than 2;
* patches: the bounded faces of the planar graph, found by a half-edge walk. A component
  drawn inside a face (not touching it) becomes a hole of that face's patch.

Half-edge ``2c`` runs along curve ``c`` from its first to its last point, ``2c + 1`` back.
Each half-edge has its face on the left; bounded faces run counter-clockwise.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import shapely

from ..arrays.components import component_labels
from ..arrays.geometry import polygons_from, shoelace_terms
from .noding import GRID, node_strokes

__all__ = ["BaseComplex", "BaseComplexError", "build_base_complex", "check_euler", "Patch"]

#: a ring of a face: (curve id, True if walked from its first point to its last)
Ring = list[tuple[int, bool]]


class BaseComplexError(RuntimeError):
    """The complex built is not a valid planar subdivision (a bug, never bad input)."""


@dataclass(eq=False)
class Patch:
    """A bounded face: its outer ring (counter-clockwise) and its holes (clockwise)."""

    boundary: Ring
    holes: list[Ring]
    area: float

    def curves(self) -> set[int]:
        """Every curve on the patch's outer ring or its holes."""
        return {c for ring in [self.boundary, *self.holes] for c, _ in ring}


@dataclass(eq=False)
class BaseComplex:
    """Nodes, curves and patches with their exact adjacency, in the sketch's unit frame."""

    nodes: np.ndarray  # (V, 2)
    node_is_auxiliary: np.ndarray  # (V,) bool: only the anchor of a lone closed loop
    curves: list[np.ndarray]  # E polylines, each (k, 2); a loop repeats its first point last
    curve_nodes: np.ndarray  # (E, 2) int: first and last node of each curve
    curve_patches: np.ndarray  # (E, 2) int: patch on the left / right of each curve, -1 none
    node_curves: list[list[int]]  # incident curve ids of each node, ascending
    patches: list[Patch]
    node_component: np.ndarray  # (V,) int connected component of each node
    num_components: int
    build_seconds: float = 0.0
    grid: float = GRID

    @property
    def num_nodes(self) -> int:
        return len(self.nodes)

    @property
    def num_curves(self) -> int:
        return len(self.curves)

    @property
    def num_patches(self) -> int:
        return len(self.patches)

    def patches_of_curve(self, curve: int) -> list[int]:
        """The 0, 1 or 2 distinct patches a curve borders (a spike inside a patch: one)."""
        return sorted({int(p) for p in self.curve_patches[curve] if p >= 0})

    def ring_points(self, ring: Ring) -> np.ndarray:
        """The points of a ring walked in order, the first point not repeated at the end."""
        parts = [self.curves[c] if fwd else self.curves[c][::-1] for c, fwd in ring]
        return np.concatenate([p[:-1] for p in parts])

    def patch_polygon(self, patch: int) -> shapely.Polygon:
        p = self.patches[patch]
        return shapely.Polygon(self.ring_points(p.boundary),
                               [self.ring_points(h) for h in p.holes])

    def euler_characteristic(self) -> int:
        """V - E + F with F the bounded faces; equals the number of connected components."""
        return self.num_nodes - self.num_curves + self.num_patches

    def summary(self) -> dict[str, float | int]:
        return {"nodes": self.num_nodes, "curves": self.num_curves,
                "patches": self.num_patches, "components": self.num_components,
                "seconds": round(self.build_seconds, 6)}


def _next_half_edges(curves: list[np.ndarray], curve_nodes: np.ndarray) -> np.ndarray:
    """For each half-edge, the one that follows it with the same face on the left."""
    num_half = 2 * len(curves)
    origin = curve_nodes.ravel()  # half-edge 2c starts at curve_nodes[c,0], 2c+1 at [c,1]
    first = np.array([[c[1] - c[0], c[-2] - c[-1]] for c in curves]).reshape(num_half, 2)
    # tie-break tangent departures (curves leaving a node in one direction) by the chord
    second = np.array([[c[min(len(c) - 1, 2)] - c[0], c[max(0, len(c) - 3)] - c[-1]]
                       for c in curves]).reshape(num_half, 2)
    angle = np.arctan2(first[:, 1], first[:, 0])
    angle2 = np.arctan2(second[:, 1], second[:, 0])
    order = np.lexsort((angle2, angle, origin))
    position = np.empty(num_half, dtype=np.intp)
    position[order] = np.arange(num_half)
    sorted_origin = origin[order]
    block_start = np.searchsorted(sorted_origin, sorted_origin, side="left")
    block_end = np.searchsorted(sorted_origin, sorted_origin, side="right")
    # previous outgoing half-edge in counter-clockwise order around the node, cyclically
    prev_pos = np.where(np.arange(num_half) == block_start, block_end - 1, np.arange(num_half) - 1)
    twin = np.arange(num_half) ^ 1
    return order[prev_pos[position[twin]]]


def _face_cycles(nxt: np.ndarray) -> tuple[np.ndarray, list[list[int]]]:
    face = np.full(len(nxt), -1, dtype=np.intp)
    cycles: list[list[int]] = []
    nxt_list = nxt.tolist()
    for h in range(len(nxt_list)):
        if face[h] >= 0:
            continue
        cycle = []
        g = h
        while face[g] < 0:
            face[g] = len(cycles)
            cycle.append(g)
            g = nxt_list[g]
        cycles.append(cycle)
    return face, cycles


def _split_rings(cycle: list[int], face_of: np.ndarray, face: int) -> list[list[int]]:
    """Split a face walk into its closed rings, leaving out curves walked both ways.

    Spikes and bridges are walked there and back inside one face walk, as nested brackets;
    what lies between a bridge's two walks is a ring of its own (a hole of the face).
    """
    rings: list[list[int]] = []
    stack: list[list[int]] = [[]]
    open_curves: set[int] = set()
    for h in cycle:
        if face_of[h ^ 1] != face:
            stack[-1].append(h)
            continue
        curve = h >> 1
        if curve in open_curves:
            open_curves.discard(curve)
            inner = stack.pop()
            if inner:
                rings.append(inner)
        else:
            open_curves.add(curve)
            stack.append([])
    # every bracket curve is walked exactly twice, so only the bottom ring is left open; a
    # walk that began inside a bracket has it split in two, which as a closed ring is fine
    if stack[0]:
        rings.append(stack[0])
    return rings


def _as_ring(half_edges: list[int]) -> Ring:
    return [(h >> 1, h % 2 == 0) for h in half_edges]


def build_base_complex(strokes: list[np.ndarray], grid: float = GRID) -> BaseComplex:
    """The base complex of polylines given in the unit-diagonal frame.

    Raises :class:`BaseComplexError` if the result breaks Euler's formula or has a bounded
    face of non-positive area: either would mean the noding missed an intersection.
    """
    t0 = time.perf_counter()
    curves = node_strokes(strokes, grid)
    if not curves:
        return _empty(time.perf_counter() - t0, grid)
    ends = np.array([[c[0], c[-1]] for c in curves]).reshape(-1, 2)
    nodes, inverse = np.unique(ends, axis=0, return_inverse=True)
    curve_nodes = inverse.reshape(-1, 2)
    degree = np.bincount(curve_nodes.ravel(), minlength=len(nodes))

    nxt = _next_half_edges(curves, curve_nodes)
    face_of, cycles = _face_cycles(nxt)
    area_of_curve = shoelace_terms(curves)
    half_area = np.stack([area_of_curve, -area_of_curve], axis=1).ravel()
    face_area = np.bincount(face_of, weights=half_area, minlength=len(cycles))

    node_component = component_labels(len(nodes), curve_nodes)
    num_components = int(node_component.max()) + 1
    face_component = node_component[curve_nodes.ravel()[[c[0] for c in cycles]]]
    by_component_then_area = np.lexsort((face_area, face_component))
    first_of_component = np.ones(len(cycles), dtype=bool)
    first_of_component[1:] = np.diff(face_component[by_component_then_area]) != 0
    outer_faces = by_component_then_area[first_of_component]
    is_outer = np.zeros(len(cycles), dtype=bool)
    is_outer[outer_faces] = True
    bad = ~is_outer & (face_area <= 0)
    if bad.any():
        raise BaseComplexError(f"{int(bad.sum())} bounded faces have non-positive area")

    bounded = np.flatnonzero(~is_outer)
    face_to_patch = np.full(len(cycles), -1, dtype=np.intp)
    face_to_patch[bounded] = np.arange(len(bounded))
    patches: list[Patch] = []
    for f in bounded.tolist():
        rings = _split_rings(cycles[f], face_of, f)
        areas = [half_area[r].sum() for r in rings]
        shell = int(np.argmax(areas))
        holes = [_as_ring(r) for i, r in enumerate(rings) if i != shell]
        patches.append(Patch(_as_ring(rings[shell]), holes, float(sum(areas))))

    complex_ = BaseComplex(
        nodes=nodes, node_is_auxiliary=degree == 2, curves=curves, curve_nodes=curve_nodes,
        curve_patches=np.empty((len(curves), 2), dtype=np.intp), node_curves=[],
        patches=patches, node_component=node_component, num_components=num_components,
        grid=grid,
    )
    _nest_components(complex_, cycles, face_of, half_area, outer_faces, face_component,
                     face_to_patch)
    complex_.curve_patches = face_to_patch[face_of].reshape(-1, 2)
    order = np.argsort(curve_nodes.ravel(), kind="stable")
    splits = np.searchsorted(curve_nodes.ravel()[order], np.arange(1, len(nodes)))
    complex_.node_curves = [sorted(set(part.tolist())) for part in np.split(order // 2, splits)]
    complex_.build_seconds = time.perf_counter() - t0
    check_euler(complex_)
    return complex_


def _nest_components(cx: BaseComplex, cycles: list[list[int]], face_of: np.ndarray,
                     half_area: np.ndarray, outer_faces: np.ndarray, face_component: np.ndarray,
                     face_to_patch: np.ndarray) -> None:
    """Make each component drawn inside a patch of another component a hole of that patch."""
    if cx.num_components < 2 or not cx.patches:
        return
    shells = polygons_from([cx.ring_points(p.boundary) for p in cx.patches])
    patch_component = cx.node_component[cx.curve_nodes[[p.boundary[0][0] for p in cx.patches], 0]]
    shell_area = shapely.area(shells)
    first_node = np.zeros(cx.num_components, dtype=np.intp)
    first_node[cx.node_component[::-1]] = np.arange(cx.num_nodes)[::-1]
    probes = shapely.points(cx.nodes[first_node])
    inside, patch = shapely.STRtree(shells).query(probes, predicate="within")
    keep = patch_component[patch] != inside
    inside, patch = inside[keep], patch[keep]
    order = np.lexsort((shell_area[patch], inside))
    inside, patch = inside[order], patch[order]
    first = np.ones(len(inside), dtype=bool)
    first[1:] = inside[1:] != inside[:-1]
    for comp, host in zip(inside[first].tolist(), patch[first].tolist()):
        face = int(outer_faces[np.flatnonzero(face_component[outer_faces] == comp)[0]])
        face_to_patch[face] = host
        for ring in _split_rings(cycles[face], face_of, face):
            cx.patches[host].holes.append(_as_ring(ring))
            cx.patches[host].area += float(half_area[ring].sum())  # clockwise: negative


def check_euler(cx: BaseComplex) -> None:
    """Fail loudly unless V - E + F = C (F bounded faces, C connected components)."""
    if cx.euler_characteristic() != cx.num_components:
        raise BaseComplexError(
            f"Euler's formula fails: V - E + F = {cx.num_nodes} - {cx.num_curves} + "
            f"{cx.num_patches} = {cx.euler_characteristic()}, but there are "
            f"{cx.num_components} components"
        )


def _empty(seconds: float, grid: float) -> BaseComplex:
    return BaseComplex(np.empty((0, 2)), np.empty(0, dtype=bool), [], np.empty((0, 2), np.intp),
                       np.empty((0, 2), np.intp), [], [], np.empty(0, np.intp), 0, seconds, grid)
