"""A graph of output edges: polylines whose ends meet at nodes.

Ends closer than ``snap`` are one node (placed at their mean), so that curves made by
merges, whose ends land near but not on a junction, still meet it. A chain of ends each
within ``snap`` of the next is cut into such groups, so that no end moves far.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..arrays.components import group_means, tight_cluster_labels
from ..arrays.geometry import unit_rows
from ..arrays.polylines import Polylines, arc_lengths, end_to_end, total_lengths

__all__ = ["Edge", "StrokeGraph", "build_graph", "end_directions", "rebuild"]


@dataclass(frozen=True)
class Edge:
    """A polyline of the output stage. Never changed: moving its ends makes a new one."""

    points: np.ndarray
    perimeter: float = np.inf  # of the smallest patch it bounds (inf: bounds none)
    free: bool = False  # bounds no patch
    closed: bool = False  # a loop: its ends are one point

    def with_ends(self, first: np.ndarray, last: np.ndarray) -> Edge:
        """The same edge with its end points moved to ``first`` and ``last``."""
        pts = self.points.copy()
        pts[0], pts[-1] = first, last
        return replace(self, points=pts)


@dataclass
class StrokeGraph:
    edges: list[Edge]
    ends: np.ndarray = field(default_factory=lambda: np.empty((0, 2), np.intp))  # (E, 2)
    nodes: np.ndarray = field(default_factory=lambda: np.empty((0, 2)))

    def degree(self) -> np.ndarray:
        return np.bincount(self.ends.ravel(), minlength=len(self.nodes))

    def lengths(self) -> np.ndarray:
        return total_lengths([e.points for e in self.edges])


def build_graph(edges: list[Edge], snap: float) -> StrokeGraph:
    """Join edge ends within ``snap`` into nodes and move the ends onto them; drop loops
    shorter than 4 * snap that this closes."""
    edges = [e for e in edges if len(e.points) >= 2]
    if not edges:
        return StrokeGraph([])
    ends = np.array([[e.points[0], e.points[-1]] for e in edges]).reshape(-1, 2)
    labels = tight_cluster_labels(ends, snap)
    nodes = group_means(ends, labels)
    edges = [e.with_ends(nodes[labels[2 * k]], nodes[labels[2 * k + 1]])
             for k, e in enumerate(edges)]
    graph = StrokeGraph(edges, labels.reshape(-1, 2), nodes)
    # a short edge whose ends snapped together is a crumb between two near crossings
    crumb = (graph.ends[:, 0] == graph.ends[:, 1]) & (graph.lengths() < 4 * snap)
    return rebuild(graph, ~crumb) if crumb.any() else graph


def rebuild(graph: StrokeGraph, keep: np.ndarray) -> StrokeGraph:
    """The graph with only the edges where ``keep`` is True, nodes renumbered."""
    edges = [e for e, k in zip(graph.edges, keep) if k]
    ends = graph.ends[keep]
    used, inverse = np.unique(ends.ravel(), return_inverse=True)
    return StrokeGraph(edges, inverse.reshape(-1, 2), graph.nodes[used])


def end_directions(polylines: list[np.ndarray], reach: float) -> np.ndarray:
    """Unit direction leaving each end of each polyline, looking ``reach`` along it:
    rows 2k (from the first point of polyline k) and 2k + 1 (from its last)."""
    walks = [w for p in polylines for w in (p, p[::-1])]
    points, first, last = end_to_end(walks)
    lines = Polylines.of_flat(arc_lengths(points, first, last), points, first, last)
    k = np.maximum(lines.index(np.arange(len(walks)), np.full(len(walks), reach)), first + 1)
    return unit_rows(points[k] - points[first])
