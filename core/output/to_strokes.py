"""From a simplified complex back to strokes (paper 3.3).

1. The linework: every curve still alive, free or on a patch outline, once, chained through
   nodes of degree 2 and cut at hairpin turns (the tips of slender patches).
2. Bi-edges: curves that still run side by side (the two long sides of a slender border
   patch, or a free curve along an outline) are merged by the curve-curve operator again,
   while the merge costs less than epsilon (:mod:`core.output.bi_edges`).
3. A graph of the edges, split where merged curves cross; overshoots past a corner or a
   crossing (short edges hanging off a junction that run straight on from a longer edge
   there) are trimmed, short details meeting a line at an angle are kept.
4. Smoothing: an edge shorter than d_eps between two junctions (and shorter than beta times
   the perimeter of the patch it bounds) is contracted to a point. This settles both of the
   paper's cases: a zigzag step becomes a node where its neighbours continue each other, and
   the short link of a confused junction merges two junctions into one crossing.
5. Joining: edges continue through nodes of degree 2, and through a junction pairwise where
   they continue each other best, turning less than ``join_angle``. The paper's test
   ``|t1 . t2| < gamma`` (gamma = cos 80 degrees) reads as "nearly perpendicular": such ends
   cross rather than continue, and never join whatever ``join_angle`` allows. Beyond the
   paper, two more joins keep a line drawn in one motion one stroke:

   * a tip: two ends left unpaired at a junction that leave it the same way (within
     ``TIP_JOIN`` degrees) are the two sides of a hairpin turn, which step 1 cut so that the
     bi-edge pass could see them face each other; where it did not merge them, they join
     again. Curls and loops of handwriting were chopped there (def: 23 strokes in, 30 out);
   * a gap: two free ends (nothing else meets them) within d_eps of each other, each
     heading on the way the other goes (within ``join_angle``), join across the gap: a gap
     narrower than the bundle width is no gap. Twice d_eps joined more, but the bridges
     left the ink (fidelity 0.40 -> 0.41 px) and joined distinct curves.
6. Whole strokes that still run side by side go through the bi-edge pass once more (every
   pair, free or not), and the strokes are joined again where merges changed them. The
   first pass judged pieces cut at every junction: a pass beside part of a long stroke
   pairs with the piece it lies along, but merged into that short piece it changes its
   shape by more than epsilon, where merged into the whole stroke it barely changes it
   (the Fourier distance measures a change against the shape it changes). On the 101 dev
   sketches: doubled ink 0.108 -> 0.095 (cartoons 0.118 -> 0.103, study drawings 0.180
   -> 0.136, product sketches 0.065 unchanged), strokes per intended curve 1.036 -> 0.990,
   at a cost in tight recall (0.825 -> 0.820: close construction lines merged as wholes)
   and distance to the ink (0.455 -> 0.463 px); ink kept unchanged. A second round merged
   little more (fruit 0.299 -> 0.260 doubled, most sketches none).
   Then bundles a little wider than d_eps: two strokes side by side up to ``FILL_REACH``
   d_eps apart merge as above when the ink between them, running along them, leaves no
   band free wider than ``fill_gap`` (the ink's spacing): one bundle drawn wide, not two
   lines drawn close (:func:`core.output.bi_edges.merge_filled_bundles`). On the 101 dev
   sketches: doubled ink 0.054 -> 0.052 (mouse7c 0.127 -> 0.034, house 0.147 -> 0.076,
   abc 0.246 -> 0.201, fruit 0.243 -> 0.203, lion 0.235 -> 0.245), strokes per intended
   curve 0.990 -> 0.962, tight recall, ink kept and distance to the ink unchanged
   (0.814, worst 0.985, 0.471 px), coverage 0.988 -> 0.986.
7. Doubled ends: a stroke whose end runs along another stroke (within ``TRIM_NEAR`` d_eps,
   for ``DOUBLED_END`` times that) and then leaves it is cut where it leaves, and starts
   on the other stroke: a pass that joins a line, runs along it and turns away, which no
   merge takes as it lies beside too little of either (:func:`trim_doubled_ends`). On the
   101 dev sketches: doubled ink 0.095 -> 0.054 (cartoons 0.103 -> 0.030, study drawings
   0.136 -> 0.100, product sketches 0.065 -> 0.057), tight recall 0.820 -> 0.814 (close
   lines that converge lose the end they share), ink kept unchanged (worst 0.985). Not
   at epsilon 0, which keeps every stroke as drawn. Gating each cut by the Fourier
   distance of the stroke before and after, as merges are, kept most doubled ends (0.076):
   a cut end is often a large part of its stroke, and yet the drawing looks the same, its
   ink within TRIM_NEAR d_eps of the line it ran along.
   An end a little farther off, up to ``TRIM_FILLED`` d_eps, is cut too where the ink
   fills the space between it and the other stroke (the test of step 6b): passes spread
   across a bundle, not two lines drawn close. On the 101 dev sketches: 27 sketches
   changed, doubled ink lower on 11 and higher on none by more than 0.005 (twirl 0.660
   -> 0.475, fruit 0.203 -> 0.153, GOEagle03 0.280 -> 0.247, grandpa 0.356 -> 0.338;
   cartoons' median 0.031 -> 0.025, the median of all unchanged at 0.052), tight recall
   0.814 -> 0.813, ink kept unchanged (worst 0.985). Without the test (every end up to
   d_eps cut) the median fell to 0.046, but the spiral test drawings lost ink (spiral3
   0.985 -> 0.974): their rings are distinct lines a bundle apart, nothing between.
8. Ends drawn through: strokes still end where lines meet wherever the ends there turn
   more than ``join_angle`` (a cusp of handwriting, a loop drawn over a crossing), and
   step 7 leaves new ends where it cut. Where the input strokes show one motion of the pen
   from one end onto another (:class:`DrawnThrough`: an input stroke passes near both
   edges and the node between them, by no longer a way than through the node), the two
   ends join, whatever the turn; ends meeting by chance, each drawn to the node, stay
   apart. Free ends across a gap narrower than d_eps (step 5's gap joins) join the same
   way. Run once on the whole strokes, after the merges and cuts: at step 5, joined
   pieces made strokes longer before the passes beside them were merged or cut, and
   doubled ink rose (ghi 0.139 -> 0.282, stu 0.055 -> 0.140). Without the node between,
   the ends of two lines side by side joined into a hairpin through the pass between
   them. On the 101 dev sketches: strokes per intended curve 0.962 -> 0.756 (study
   drawings 1.780 -> 1.172: def 22 strokes -> 13, vwx 20 -> 10; product sketches 0.915
   -> 0.733, cartoons 0.812 -> 0.679), doubled ink 0.041 -> 0.036 (study drawings 0.104
   -> 0.075), tight recall 0.836 -> 0.835, distance to the ink 0.500 -> 0.506 px, ink
   kept unchanged (worst 0.987). On 89 sketches held out from the same three sources:
   strokes per intended curve 0.867 -> 0.738, doubled ink unchanged (0.042), and
   siggraph (29 strokes in, 33 out) comes out as 23 strokes.
9. Placement: each line moves onto the middle of the input ink it stands for, junctions
   held (:mod:`core.output.placement`). Not at epsilon 0.
10. Junctions: an end that stops within ``tuning.snap`` d_eps of another line meets it
    exactly (:mod:`core.output.junctions`, the pen stage's pass 9), and two free ends that
    both stop short of the corner they draw (each within ``tuning.corner`` d_eps) meet
    there; an overshoot is left as drawn (cut, whole lines fell by 0.006 and Chamfer rose
    0.02 px on lift3d, where extending alone raised whole lines; docs/decisions.md).
    Lines chained from the complex's pieces stopped short of the line they meet: of the
    open ends within two widths of another line, 15% touched it. Not at epsilon 0.
11. Each stroke is fitted with piecewise cubic Beziers, corners kept; an end that met a
    line is moved again onto that line's fitted curve.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import shapely

from ..arrays.components import component_labels, group_means, wider_than
from ..arrays.geometry import (
    directions_at,
    lines_from,
    nearest_on,
    split_coordinates,
    tangents,
)
from ..arrays.polylines import (
    arc_lengths,
    leading_count,
    points_at,
    resample_polyline,
    total_lengths,
)
from ..complex.complex_state import ComplexState
from ..complex.noding import GRID
from ..curves.attributes import InkRows, NearestInk
from ..curves.bezier import (
    corner_indices,
)
from ..curves.memo import StrokeMemo, shape_key
from ..lines.bezier import FittedStroke, fit_lines
from ..lines.junctions import meet_at_junctions, met_ends
from ..params import SimplifyParams
from .bi_edges import InkFill, merge_bi_edges, merge_filled_bundles
from .junctions import meet_at_corners
from .placement import PLACE_REACH, centred_on_ink
from .stroke_graph import Edge, StrokeGraph, build_graph, end_directions, rebuild

__all__ = [
    "DOUBLED_END", "DoubledEnd", "DrawnThrough", "EXACT_JUNCTION", "FittedStroke",
    "THROUGH_DETOUR", "TIP_JOIN", "TRIM_FILLED", "TRIM_NEAR", "close_loops", "continuations",
    "contract_short_edges", "fit_lines", "join_edges", "linework", "renode", "split_at_tips",
    "to_strokes", "trim_doubled_ends", "trim_spurs",
]


def linework(state: ComplexState) -> list[Edge]:
    """The alive curves, each with the perimeter of the smallest patch it bounds."""
    alive = state.alive_curves()
    lengths = dict(zip(alive, total_lengths([state.curves[c] for c in alive]).tolist()))
    perim = {p: sum(lengths[c] for c in state.patch_curves[p]) for p in state.alive_patches()}
    edges = []
    for c in alive:
        free = state.is_free(c)
        sides = [perim[p] for p in state.curve_sides[c] if p >= 0 and not free]
        edges.append(Edge(state.curves[c], min(sides, default=np.inf), free))
    return edges


def renode(edges: list[Edge]) -> list[Edge]:
    """Split edges where they cross: merged curves are drawn anew and cross without nodes.

    Each piece keeps the perimeter of the edge it lies on.
    """
    if not edges:
        return edges
    lines = lines_from([e.points for e in edges])
    pieces = shapely.get_parts(shapely.line_merge(shapely.unary_union(lines, grid_size=GRID)))
    pieces = pieces[(shapely.get_type_id(pieces) == 1) & (shapely.length(pieces) > 0)]
    mids = shapely.line_interpolate_point(pieces, 0.5, normalized=True)
    owner = shapely.STRtree(lines).query_nearest(mids, all_matches=False)[1]
    return [Edge(pts, edges[k].perimeter, edges[k].free)
            for pts, k in zip(split_coordinates(pieces), owner.tolist())]


#: dangling edges up to this many d_eps long that run straight on from a longer edge
#: through a junction are trimmed: overshoots past a corner or a crossing
SPUR_LENGTH = 3.0


def trim_spurs(graph: StrokeGraph, d_eps: float, cos_join: float) -> StrokeGraph:
    """Drop overshoots: short edges hanging off a junction by one free end that continue a
    longer edge there (leaving the junction opposite to it, within the join angle), and
    crumbs shorter than d_eps whatever their direction where an edge at least d_eps long
    meets them (where every edge at a junction is a crumb, they are a drawing smaller than
    d_eps, and stay).

    A short edge meeting a line at an angle (a fret across a neck, a whisker, the stem of
    a T) is a detail of the drawing, and stays. Of two short edges that continue each
    other (a tick across a line), the shorter goes.
    """
    for _ in range(2):
        if not graph.edges:
            return graph
        deg = graph.degree()
        lengths = graph.lengths()
        da, db = deg[graph.ends[:, 0]], deg[graph.ends[:, 1]]
        hanging = (lengths < SPUR_LENGTH * d_eps) & (((da == 1) & (db >= 3))
                                                     | ((db == 1) & (da >= 3)))
        if not hanging.any():
            break
        # a crumb goes only where a line stays at its junction: an edge at least d_eps
        # long there (three crumbs meeting are a small drawing, not its overshoots)
        node_of_end = graph.ends.ravel()
        junction = np.where(da == 1, graph.ends[:, 1], graph.ends[:, 0])
        stays = np.zeros(int(node_of_end.max()) + 1, bool)
        stays[node_of_end[np.repeat(lengths >= d_eps, 2)]] = True
        spur = hanging & (lengths < d_eps) & stays[junction]
        directions = end_directions([e.points for e in graph.edges], 2 * d_eps)
        for k in np.flatnonzero(hanging & ~spur).tolist():
            end = 2 * k + int(da[k] == 1)  # the end at the junction
            others = np.flatnonzero(node_of_end == node_of_end[end])
            others = others[others >> 1 != k]
            longer = (lengths[others >> 1] > lengths[k]) | (
                (lengths[others >> 1] == lengths[k]) & (others >> 1 > k))
            spur[k] = bool(np.any(longer & (directions[others] @ -directions[end] >= cos_join)))
        if not spur.any():
            break
        graph = rebuild(graph, ~spur)
    return graph


def contract_short_edges(graph: StrokeGraph, d_eps: float, beta: float) -> StrokeGraph:
    """Contract short edges between junctions to a point (zigzags, confused junctions)."""
    if not graph.edges:
        return graph
    deg = graph.degree()
    lengths = graph.lengths()
    perim = np.array([e.perimeter for e in graph.edges])
    a, b = graph.ends[:, 0], graph.ends[:, 1]
    short = ((lengths < d_eps) & (lengths < beta * perim) & (deg[a] >= 3) & (deg[b] >= 3)
             & (a != b))
    if not short.any():
        return graph
    # short edges in a row (a curve drawn as many short links between crossings) would
    # pull a whole stretch of drawing to one point: a group wider than d_eps stays
    root = component_labels(len(graph.nodes), graph.ends[short])
    short &= ~wider_than(graph.nodes, root, d_eps)[root[a]]
    if not short.any():
        return graph
    root = component_labels(len(graph.nodes), graph.ends[short])
    centre = group_means(graph.nodes, root)
    ends = root[graph.ends]
    moved = StrokeGraph([e.with_ends(centre[ends[k, 0]], centre[ends[k, 1]])
                         for k, e in enumerate(graph.edges)], ends, centre)
    return rebuild(moved, ~short | (ends[:, 0] != ends[:, 1]))


#: junctions with more ends than this pair them greedily, smoothest first: the exact
#: matching looks at 2^n sets of ends (a busy junction of a dense sketch has dozens)
EXACT_JUNCTION = 10


def continuations(n: int, smooth: dict[tuple[int, int], float]) -> list[tuple[int, int]]:
    """Which of ``n`` ends meeting at a junction continue each other: as many of the
    ``smooth`` pairs (x < y, with how straight each continues, a cosine) as can be taken
    together, and of those the straightest in all.

    Taking the straightest pair first, as a greedy pairing does, can leave two lines cut
    where a fork of passes meets another line: ends 0-1 continue best, and then 2 and 3
    fit neither; 0-2 and 1-3, each smooth, continue both lines.

    >>> continuations(4, {(0, 1): 0.98, (0, 2): 0.91, (1, 3): 0.96})
    [(0, 2), (1, 3)]
    """
    if n > EXACT_JUNCTION:  # greedy, smoothest first
        used: set[int] = set()
        chosen = []
        for (x, y), _ in sorted(smooth.items(), key=lambda item: -item[1]):
            if x not in used and y not in used:
                used.update((x, y))
                chosen.append((x, y))
        return sorted(chosen)
    partners: dict[int, list[tuple[int, float]]] = {}
    for (x, y), cos in smooth.items():
        partners.setdefault(x, []).append((y, cos))
    best: dict[int, tuple[int, float, tuple]] = {}

    def match(free: int) -> tuple[int, float, tuple]:
        """The best matching of the ends in bitmask ``free``: (pairs, total cos, pairs)."""
        if free in best:
            return best[free]
        if free == 0:
            return 0, 0.0, ()
        x = (free & -free).bit_length() - 1  # the lowest free end: paired, or left alone
        result = match(free & ~(1 << x))
        for y, cos in partners.get(x, ()):
            if free >> y & 1:
                count, total, pairs = match(free & ~(1 << x) & ~(1 << y))
                if (count + 1, total + cos) > result[:2]:
                    result = (count + 1, total + cos, ((x, y), *pairs))
        best[free] = result
        return result

    return sorted(match((1 << n) - 1)[2])


#: two ends leaving a junction within this many degrees of each other are a hairpin's
#: sides (step 5 of the module docstring)
TIP_JOIN = 25.0


def _bridge_gaps(graph: StrokeGraph, link: np.ndarray, directions: np.ndarray, gap: float,
                 cos_join: float, through: DrawnThrough | None = None) -> None:
    """Link free ends (their node has no other edge, no link yet) within ``gap`` of each
    other that continue each other, or (``through`` given) that an input stroke runs from
    one onto the other, nearest first."""
    at = graph.nodes[graph.ends.ravel()]  # where each end is
    free = np.flatnonzero((graph.degree()[graph.ends.ravel()] == 1) & (link < 0))
    if len(free) < 2:
        return
    points = shapely.points(at[free])
    x, y = shapely.STRtree(points).query(points, predicate="dwithin", distance=gap)
    keep = (x < y) & (free[x] >> 1 != free[y] >> 1)
    x, y = free[x[keep]], free[y[keep]]
    smooth = -(directions[x] * directions[y]).sum(axis=1) >= cos_join
    if through is not None:
        smooth |= np.fromiter((through.drawn(a, b) for a, b in zip(x.tolist(), y.tolist())),
                              dtype=bool, count=len(x))
    x, y = x[smooth], y[smooth]
    dist = np.hypot(*(at[x] - at[y]).T)
    for k in np.lexsort((y, x, dist)).tolist():
        a, b = int(x[k]), int(y[k])
        if link[a] < 0 and link[b] < 0:
            link[a], link[b] = b, a


#: an input stroke is drawn through a junction from one edge onto another when it passes
#: near a point of each and runs between them no longer than this many times the way from
#: one point to the other through the junction (step 8 of the module docstring)
THROUGH_DETOUR = 1.5


@dataclass(frozen=True)
class DrawnThrough:
    """Which ends of a graph's edges an input stroke runs through, from one onto the other
    (step 8 of the module docstring).

    Each end has a probe: the point of its edge ``reach`` from it (half the edge, if that
    is shorter). An input stroke that passes within ``reach / 2`` of the probes of two
    ends, and of their nodes between the two, running from probe to probe no longer than
    :data:`THROUGH_DETOUR` times the way from probe to node (to node) to probe (and the
    radius either side), was drawn from one edge onto the other: one motion of the pen,
    whatever the turn. Passing near both probes alone is not enough: the two ends of two
    lines side by side have probes side by side, and a pass between them near both.
    """

    way: np.ndarray  #: (2E,) how far each end's probe lies from the end's node
    end_node: np.ndarray  #: (2E,) the node of each end
    nodes: np.ndarray  #: (V, 2) where each node is
    at_probe: InkRows  #: the ink near each end's probe
    at_node: InkRows  #: the ink near each node
    radius: float

    @classmethod
    def of(cls, graph: StrokeGraph, ink: NearestInk, reach: float) -> DrawnThrough:
        walks = [w for e in graph.edges for w in (e.points, e.points[::-1])]
        along = np.minimum(reach, 0.5 * np.repeat(graph.lengths(), 2))
        probes = shapely.get_coordinates(shapely.line_interpolate_point(lines_from(walks),
                                                                        along))
        end_node = graph.ends.ravel()
        return cls(np.hypot(*(probes - graph.nodes[end_node]).T), end_node, graph.nodes,
                   ink.passing(probes, reach / 2), ink.passing(graph.nodes, reach / 2),
                   reach / 2)

    def drawn(self, x: int, y: int) -> bool:
        """Whether an input stroke runs from end ``x`` through their node (or across the gap
        between their nodes) onto end ``y``.

        Rows are one per input segment near a point, so a densely sampled stroke gives
        thousands; comparing every row near one probe with every row near the other took
        gigabytes on a 100,000-point stroke. The running arc length orders the rows by
        stroke too (a gap of 1 between strokes), so for each pass near ``x`` only the
        farthest pass near ``y`` on either side of it along the same stroke is compared:
        the span between them holds any nearer one's, so it passes near the nodes if any
        does. Sorting and binary search, O(n log n)."""
        sx, ax = self.at_probe.of(x)
        sy, ay = self.at_probe.of(y)
        if not len(ax) or not len(ay):
            return False
        nx, ny = int(self.end_node[x]), int(self.end_node[y])
        way = self.way[x] + np.hypot(*(self.nodes[nx] - self.nodes[ny])) + self.way[y]
        reach = THROUGH_DETOUR * way + 2 * self.radius
        order = np.argsort(ay, kind="stable")
        sy, ay = sy[order], ay[order]  # sorted by running arc length, so by stroke too
        up = np.minimum(np.searchsorted(ay, ax + reach, "right"),
                        np.searchsorted(sy, sx, "right")) - 1
        down = np.maximum(np.searchsorted(ay, ax - reach, "left"),
                          np.searchsorted(sy, sx, "left"))
        up_c, down_c = np.clip(up, 0, len(ay) - 1), np.clip(down, 0, len(ay) - 1)
        ok_up = (up >= 0) & (sy[up_c] == sx) & (ay[up_c] >= ax)
        ok_down = (down < len(ay)) & (sy[down_c] == sx) & (ay[down_c] <= ax)
        lo = np.concatenate([ax[ok_up], ay[down_c[ok_down]]])
        hi = np.concatenate([ay[up_c[ok_up]], ax[ok_down]])
        for node in dict.fromkeys((nx, ny)):  # and near the node(s) on the way
            an = np.sort(self.at_node.of(node)[1])  # within [lo, hi]: the same stroke
            if not len(an):
                return False
            first = np.searchsorted(an, lo, "left")
            keep = (first < len(an)) & (an[np.minimum(first, len(an) - 1)] <= hi)
            lo, hi = lo[keep], hi[keep]
        return len(lo) > 0


def join_edges(graph: StrokeGraph, params: SimplifyParams, at_junctions: bool = True,
               ink: NearestInk | None = None) -> list[Edge]:
    """Chain edges through degree-2 nodes and, if asked, junctions, tips and small gaps
    (step 5 of the module docstring).

    ``ink`` given (step 8): whole strokes, ends meeting at a node are joined only where
    they continue each other, or an input stroke runs through the node from one onto the
    other (:class:`DrawnThrough`), or they are a hairpin's sides; two ends alone at a node
    are not chained for that alone."""
    n_edges = len(graph.edges)
    reach = 2 * params.resolved().alpha
    link = np.full(2 * n_edges, -1)  # end 2k (start of edge k) / 2k+1 (its end) -> partner
    cos_join = np.cos(np.radians(params.join_angle))
    cos_tip = np.cos(np.radians(TIP_JOIN))
    directions = end_directions([e.points for e in graph.edges], reach) if n_edges else None
    through = DrawnThrough.of(graph, ink, reach) if ink is not None and n_edges else None
    by_node: dict[int, list[int]] = {}
    for k in range(n_edges):
        for side in (0, 1):
            by_node.setdefault(int(graph.ends[k, side]), []).append(2 * k + side)
    for _node, ends in sorted(by_node.items()):
        if len(ends) < 2 or (len(ends) > 2 and not at_junctions):
            continue
        dirs = [directions[e] for e in ends]
        if len(ends) == 2 and through is None:
            if ends[0] >> 1 != ends[1] >> 1:
                link[ends[0]], link[ends[1]] = ends[1], ends[0]
            continue
        # continuing straight: leaving directions opposite, cos = -(d1 . d2) close to 1
        smooth = {(x, y): cos for x in range(len(ends)) for y in range(x + 1, len(ends))
                  if (cos := float(-(dirs[x] @ dirs[y]))) >= cos_join
                  and abs(cos) >= params.gamma and ends[x] >> 1 != ends[y] >> 1}
        paired = continuations(len(ends), smooth)
        used = {v for pair in paired for v in pair}
        if through is not None:  # then one motion of the pen, whatever the turn
            left = [x for x in range(len(ends)) if x not in used]
            drawn = continuations(len(ends), {
                (x, y): float(-(dirs[x] @ dirs[y])) for i, x in enumerate(left)
                for y in left[i + 1:]
                if ends[x] >> 1 != ends[y] >> 1 and through.drawn(ends[x], ends[y])})
            paired += drawn
            used.update(v for pair in drawn for v in pair)
        tips = {(x, y): cos for x in range(len(ends)) for y in range(x + 1, len(ends))
                if x not in used and y not in used and ends[x] >> 1 != ends[y] >> 1
                and (cos := float(dirs[x] @ dirs[y])) >= cos_tip}
        for x, y in paired + continuations(len(ends), tips):
            link[ends[x]], link[ends[y]] = ends[y], ends[x]
    if at_junctions:
        _bridge_gaps(graph, link, directions, reach / 2, cos_join, through)
    strokes = []
    done = np.zeros(n_edges, dtype=bool)

    def walk(start_end: int) -> Edge:
        parts, perimeter, free = [], np.inf, True
        e = start_end  # we enter edge e >> 1 at end e and leave at the other end
        closed = False
        while True:
            k = e >> 1
            done[k] = True
            pts = graph.edges[k].points
            parts.append(pts if e % 2 == 0 else pts[::-1])
            perimeter = min(perimeter, graph.edges[k].perimeter)
            free = free and graph.edges[k].free
            nxt = link[e ^ 1]
            if nxt < 0:
                break
            if done[nxt >> 1]:
                closed = nxt == start_end
                break
            e = nxt
        # parts meet at a shared node, or across a bridged gap (both points kept)
        pts = np.concatenate([parts[0]] + [p[1:] if np.array_equal(p[0], q[-1]) else p
                                           for q, p in zip(parts, parts[1:])])
        if closed and not np.array_equal(pts[0], pts[-1]):
            pts = np.vstack([pts, pts[:1]])
        return Edge(pts, perimeter, free, closed)

    for k in range(n_edges):  # open chains first: start where no link enters
        for side in (0, 1):
            if not done[k] and link[2 * k + side] < 0:
                strokes.append(walk(2 * k + side))
    for k in range(n_edges):  # what is left are closed loops
        if not done[k]:
            strokes.append(walk(2 * k))
    return strokes


def close_loops(strokes: list[Edge], d_eps: float) -> list[Edge]:
    """Close the open strokes that end where they began (both ends on one node), and those
    that come back over their own start (:func:`_run_over_its_start`) or, failing that,
    whose ends overshoot each other (:func:`_past_its_start`)."""
    out = []
    for e in strokes:
        pts = e.points
        if e.closed or len(pts) < 4:
            out.append(e)
            continue
        if np.array_equal(pts[0], pts[-1]):  # a chain whose ends met at one node
            out.append(replace(e, closed=True))
            continue
        s = arc_lengths(pts)
        loop = None
        if s[-1] >= 8 * d_eps:
            loop = _run_over_its_start(pts, s, d_eps)
            if loop is None:
                loop = _past_its_start(pts, s, d_eps)
        if loop is None:
            out.append(e)
            continue
        loop[-1] = loop[0]
        out.append(replace(e, points=loop, closed=True))
    return out


def _run_over_its_start(pts: np.ndarray, s: np.ndarray, d_eps: float) -> np.ndarray | None:
    """The loop of a stroke that comes back over its own start: the last point within
    d_eps of the first stretch, heading the way the stroke set out there (a loop drawn in
    pieces that overlap where they meet). The overlap is cut: the loop starts where the
    last point lies beside the first stretch. None when the stroke does not."""
    first = np.flatnonzero(s <= s[-1] / 3)  # the first third: the stroke's own start
    gaps = np.hypot(*(pts[first] - pts[-1]).T)
    k = int(first[np.argmin(gaps)])
    heading_out = pts[min(k + 1, len(pts) - 1)] - pts[max(k - 1, 0)]
    heading_in = pts[-1] - pts[-2]
    turned = heading_out @ heading_in <= 0.5 * np.hypot(*heading_out) * np.hypot(*heading_in)
    if gaps.min() > d_eps or k == 0 or turned:
        return None
    loop = pts[k:].copy()
    cut = shapely.distance(shapely.points(pts[:k]), shapely.LineString(loop))
    if cut.max() > d_eps:  # the stretch cut off is not run over again: no loop
        return None
    return loop


def _past_its_start(pts: np.ndarray, s: np.ndarray, d_eps: float) -> np.ndarray | None:
    """The loop of a stroke whose two ends overshoot each other (a corner drawn past, as
    overshoots are), closed where it passes its own start: a point of its last SPUR_LENGTH
    d_eps within d_eps of a point of its first; of those pairs, the one that cuts the least
    ink off the two ends. None when there is none. (Without this, a rough square whose
    sides overshoot its corners by 1 to 3% of D came out as one open stroke, an overshoot
    hanging off a corner, at widths of 1.3% of D and more.)"""
    reach = SPUR_LENGTH * d_eps
    head = np.flatnonzero(s <= reach)
    tail = np.flatnonzero(s >= s[-1] - reach)
    gaps = np.hypot(*(pts[head][:, None, :] - pts[tail][None, :, :]).transpose(2, 0, 1))
    cut = s[head][:, None] + (s[-1] - s[tail])[None, :]
    cut = np.where(gaps <= d_eps, cut, np.inf)
    i, j = np.unravel_index(int(np.argmin(cut)), cut.shape)
    if not np.isfinite(cut[i, j]):
        return None
    return pts[head[i]:tail[j] + 1].copy()


#: a stroke's end that runs within TRIM_NEAR d_eps of another stroke for at least
#: DOUBLED_END times that distance, and then leaves it, is that line drawn twice there: it
#: is cut where it leaves (trim_doubled_ends). A cut removes ink outright, where a merge
#: puts a line between the two, so it keeps closer than d_eps: at 1.0 d_eps the spiral
#: test drawings, whose ink spans more than their canvas, lost ink (kept 0.971 against
#: 0.985), and tight recall fell 0.820 -> 0.812 (0.814 at 0.75; doubled 0.044 and 0.054)
TRIM_NEAR = 0.75
DOUBLED_END = 2.0

#: an end that runs farther than TRIM_NEAR d_eps from the other stroke, up to this many
#: d_eps, is cut too where the ink fills the space between the two (:class:`InkFill`):
#: one bundle drawn a little wide, not two lines drawn close (a spiral's rings, close
#: construction lines), whose ends a cut would take away. Also cutting where the ink a
#: cut leaves behind stays within (1 - fit_error) d_eps of the output, filled or not, cut
#: no more (median doubled ink 0.052 either way); within d_eps the spirals lose ink
#: (spiral3 0.974), as their canvas is smaller than their ink
TRIM_FILLED = 1.0


def _doubled_run(pts: np.ndarray, spacing: float, others: list[int], lines: np.ndarray,
                 reach: float, cos_max: float) -> tuple[int, int]:
    """How many samples ``pts`` (every ``spacing``) from its start lie within ``reach`` of
    one of the ``others`` lines, running along it (tangents within the angle), and which
    (-1: none)."""
    best, which = 0, -1
    if not others:
        return best, which
    first = shapely.distance(shapely.points(pts[0]), lines[others]) <= reach
    if not first.any():  # most ends lie by no other stroke
        return best, which
    others = [j for j, ok in zip(others, first.tolist()) if ok]
    geoms = shapely.points(pts)
    tangent = tangents(pts)
    near = shapely.distance(geoms[:, None], lines[others][None, :]) <= reach  # all at once
    runs = leading_count(near).tolist()
    for j, run in zip(others, runs):
        if run <= best:
            continue
        direction = directions_at(lines[j], geoms[:run], spacing / 2)
        along = np.abs((direction * tangent[:run]).sum(axis=1)) >= cos_max
        run = leading_count(along)
        if run > best:
            best, which = run, j
    return best, which


@dataclass(frozen=True)
class DoubledEnd:
    """A stroke's end drawn twice (:func:`trim_doubled_ends`), from the end it starts at."""

    other: int  #: the stroke it runs along
    cut: float  #: where it leaves that stroke, as an arc length from the end
    back: np.ndarray  #: the point of the run a reach back from the cut


def _doubled_end(line_pts: np.ndarray, reach: float, others: list[int], lines: np.ndarray,
                 cos_max: float, per_reach: int) -> DoubledEnd | None:
    """The doubled end of ``line_pts`` at its start, at ``reach``, or None."""
    samples = resample_polyline(line_pts, reach / per_reach)
    step = float(arc_lengths(samples)[-1]) / max(len(samples) - 1, 1)
    run, j = _doubled_run(samples, step, others, lines, reach, cos_max)
    if run * step < DOUBLED_END * reach or len(samples) - run < 4:
        return None
    # cut at the last sample beside the other line
    return DoubledEnd(j, (run - 1) * step, samples[max(run - 1 - per_reach, 0)])


def _filled(end: DoubledEnd, line_pts: np.ndarray, s: np.ndarray, lines: np.ndarray,
            fill: InkFill, reach: float) -> bool:
    """Whether ink fills the space between a doubled end (of ``line_pts``, arc lengths
    ``s``) and the stroke it runs along."""
    piece = np.vstack([line_pts[s < end.cut], points_at(np.array([end.cut]), s, line_pts)])
    pair = np.array([shapely.linestrings(piece), lines[end.other]])
    return bool(fill.pairs(pair, np.array([0]), np.array([1]), reach)[0])


def trim_doubled_ends(strokes: list[Edge], reach: float, max_angle_deg: float,
                      fill: InkFill | None = None, filled_reach: float = 0.0) -> list[Edge]:
    """Cut the ends of open strokes that run within ``reach`` of another stroke, along it,
    for DOUBLED_END times ``reach`` and then leave it: the end is that line drawn twice (a
    pass that joins a line, runs along it and turns away: it lies beside too little of
    either stroke for a merge to take it). The end is cut where it leaves, and the stroke
    starts on the line it ran along, a little back (a fork, not a tick across the gap).
    An end that does not, but runs so within ``filled_reach`` (for DOUBLED_END times
    that), is cut too where ink fills the space between it and the other stroke
    (``fill``).

    Shorter strokes are trimmed first, each against the strokes as trimmed so far, so that
    of two strokes overlapping end to end only one gives up its end. Strokes left alone
    are returned as they were (the same points).
    """
    if len(strokes) < 2:
        return strokes
    cos_max = np.cos(np.radians(max_angle_deg))
    per_reach = 4  # samples: an end is measured every reach / 4
    out = list(strokes)
    lines = lines_from([e.points for e in out])
    tree = shapely.STRtree(lines.copy())  # candidates: the strokes before any trimming
    lengths = shapely.length(lines)
    for i in np.argsort(lengths, kind="stable").tolist():
        e = out[i]
        if e.closed or lengths[i] < 2 * DOUBLED_END * reach:
            continue
        others = [int(j) for j in tree.query(lines[i], predicate="dwithin",
                                             distance=max(reach, filled_reach)) if j != i]
        if not others:
            continue
        pts = e.points
        for side in (0, 1):
            line_pts = pts if side == 0 else pts[::-1]
            s = arc_lengths(line_pts)
            end = _doubled_end(line_pts, reach, others, lines, cos_max, per_reach)
            if end is None and fill is not None and filled_reach > reach:
                end = _doubled_end(line_pts, filled_reach, others, lines, cos_max, per_reach)
                if end is not None and not _filled(end, line_pts, s, lines, fill,
                                                   filled_reach):
                    end = None
            if end is None:
                continue
            keep = line_pts[s > end.cut]
            start = points_at(np.array([end.cut]), s, line_pts)
            # it starts on the other line a reach back along the run: a shallow fork
            onto = nearest_on(lines[end.other], shapely.points(end.back))
            line_pts = np.vstack([onto, start, keep])
            pts = line_pts if side == 0 else line_pts[::-1]
        if pts is not e.points:
            out[i] = replace(e, points=pts)
            lines[i] = shapely.linestrings(pts)
    return out


#: turns sharper than this, in degrees, are the tips of slender border patches
TIP_ANGLE = 100.0


def split_at_tips(chains: list[Edge], d_eps: float, memo: StrokeMemo) -> list[Edge]:
    """Cut chains at hairpin turns, and loops without one in two halves, so that the two
    long sides of a slender patch face each other as two edges."""
    out = []
    for e in chains:
        pts = e.points
        key = shape_key(pts, e.closed)
        cuts = memo.tips.get(key)
        if cuts is None:
            cuts = corner_indices(pts, TIP_ANGLE, d_eps)
            if e.closed and not cuts:
                far = int(np.argmax(np.hypot(*(pts - pts[0]).T)))
                cuts = [far] if 0 < far < len(pts) - 1 else []
            memo.tips.put(key, cuts)
        bounds = [0, *cuts, len(pts) - 1]
        out += [Edge(pts[i:j + 1], e.perimeter, e.free) for i, j in zip(bounds[:-1], bounds[1:])
                if j > i]
    return out


def _joined_again(merged: list[Edge], strokes: list[Edge], params: SimplifyParams,
                  snap: float) -> list[Edge]:
    """The strokes after a pass over whole strokes (``merged``, from ``strokes``): joined
    again through the nodes where merges changed them, or ``strokes`` as they were when
    the pass merged none. ``params`` resolved (alpha a number, d_eps)."""
    if len(merged) >= len(strokes):
        return strokes
    return close_loops(join_edges(build_graph(renode(merged), snap), params), params.alpha)


def to_strokes(state: ComplexState, params: SimplifyParams, memo: StrokeMemo,
               ink: NearestInk | None = None) -> list[FittedStroke]:
    """Output strokes (unit frame) of a simplified complex; ``ink``, the input strokes,
    for steps 8 and 9 (without: neither).

    ``memo`` keeps Bezier fits and the bi-edge pass's work by content: results replayed at
    other epsilons (a slider) share most strokes and most pairs of edges.
    """
    params = params.resolved()  # alpha a number
    d_eps = params.alpha
    snap = d_eps / 2
    chains = join_edges(build_graph(linework(state), snap), params, at_junctions=False)
    edges = merge_bi_edges(split_at_tips(chains, d_eps, memo), params, memo)
    graph = build_graph(renode(edges), snap)
    graph = trim_spurs(graph, d_eps, np.cos(np.radians(params.join_angle)))
    graph = contract_short_edges(graph, d_eps, params.beta)
    joined = close_loops(join_edges(graph, params), d_eps)
    # step 6: whole strokes that still run side by side, every pair judged (the merge loop
    # judged free curves only as the pieces they were then)
    joined = _joined_again(merge_bi_edges(joined, params, memo, every_pair=True), joined,
                           params, snap)
    if params.epsilon > 0:  # epsilon 0 keeps every stroke as drawn
        # step 6b: bundles a little wider than d_eps, filled with ink
        fill = InkFill.of(state.base.curves, params)
        joined = _joined_again(merge_filled_bundles(joined, params, memo, fill), joined,
                               params, snap)
        joined = trim_doubled_ends(joined, TRIM_NEAR * d_eps, params.angle,  # step 7
                                   fill, TRIM_FILLED * d_eps)
        if ink is not None:  # step 8: ends drawn through a junction
            joined = close_loops(join_edges(build_graph(joined, snap), params, ink=ink), d_eps)
    lines, closed = [], []
    for stroke in joined:
        if arc_lengths(stroke.points)[-1] <= GRID:  # a crumb below the snapping grid
            continue
        # evenly spaced at a quarter of d_eps: enough for the fit, and no hundreds of
        # points where the input was dense
        lines.append(resample_polyline(stroke.points, d_eps / 4))
        closed.append(stroke.closed)
    if ink is not None and params.epsilon > 0:  # step 9: onto the middle of their ink
        lines = centred_on_ink(lines, closed, ink, PLACE_REACH * d_eps, d_eps / 4)
    if params.epsilon == 0 or len(lines) < 2:
        return fit_lines(lines, closed, params, memo)
    t = params.tuning  # step 10: junctions
    cos_max = float(np.cos(np.radians(params.angle)))
    lines, meets = meet_at_junctions(lines, closed, t.snap * d_eps, t.overshoot * d_eps,
                                     cos_max, d_eps / 4, cut=False)
    lines, meets = meet_at_corners(lines, closed, meets, t.corner * d_eps, cos_max, d_eps / 4)
    return met_ends(fit_lines(lines, closed, params, memo), meets)
