"""The output graph: edge ends snapped into nodes, without chaining along close lines."""

from __future__ import annotations

import tracemalloc

import numpy as np
import shapely

from core.arrays.components import cluster_labels, tight_cluster_labels
from core.arrays.geometry import lines_from
from core.curves.attributes import InkRows
from core.output.bi_edges import InkFill
from core.output.stroke_graph import Edge, build_graph
from core.output.to_strokes import THROUGH_DETOUR, DrawnThrough, trim_doubled_ends


def test_ends_within_snap_become_one_node():
    edges = [Edge(np.array([(0, 0), (10, 0)], float)), Edge(np.array([(10.2, 0.1), (10, 10)])),
             Edge(np.array([(9.9, -0.1), (20, 0)]))]
    graph = build_graph(edges, 0.5)
    assert len(graph.nodes) == 4
    assert sorted(graph.degree().tolist()) == [1, 1, 1, 3]
    assert np.allclose(graph.edges[1].points[0], graph.edges[0].points[-1])


def test_ends_along_two_close_lines_are_not_pulled_to_one_point():
    # edges 3 long along two lines 0.4 apart, one starting every 0.3: single linkage
    # chains every end into one cluster 20 long
    x = np.arange(0, 17, 0.3)
    edges = [Edge(np.array([(a, y), (a + 3, y)])) for y in (0.0, 0.4) for a in x]
    ends = np.array([e.points[[0, -1]] for e in edges]).reshape(-1, 2)
    assert len(np.unique(cluster_labels(ends, 0.5))) == 1
    graph = build_graph(edges, 0.5)
    moved = np.array([e.points[[0, -1]] for e in graph.edges]).reshape(-1, 2) - ends
    assert np.hypot(*moved.T).max() <= 1.0  # at most twice the snap
    assert len(graph.nodes) > 15


def test_tight_clusters_are_the_single_linkage_ones_where_those_are_small():
    rng = np.random.default_rng(3)
    centres = rng.uniform(0, 100, (40, 2))
    points = np.repeat(centres, 5, axis=0) + rng.normal(0, 0.05, (200, 2))
    assert np.array_equal(tight_cluster_labels(points, 0.5), cluster_labels(points, 0.5))
    labels = tight_cluster_labels(np.array([(0, 0), (0.4, 0), (0.8, 0), (1.2, 0), (1.6, 0.0)]),
                                  0.5)
    assert labels.tolist() == [0, 0, 1, 1, 2]


def _along_then_away(run: float, offset: float) -> np.ndarray:
    """A stroke that runs ``run`` along the x axis, ``offset`` above it, then turns 45
    degrees away for 5 units."""
    x = np.linspace(2.0, 2.0 + run, 40)
    along = np.column_stack([x, np.full_like(x, offset)])
    t = np.linspace(0, 5, 40)[1:, None] / np.sqrt(2)
    return np.vstack([along, along[-1] + np.hstack([t, t])])


def test_a_stroke_end_run_along_a_line_then_away_is_cut_where_it_leaves():
    """reach 1: a stroke 0.5 above a line for 3 units, then away, loses that run and
    starts on the line; one beside it for 1 unit only, one crossing it, and a loop along
    it are left as they were (the same points)."""
    line = Edge(np.array([[0.0, 0.0], [20.0, 0.0]]))
    fork = Edge(_along_then_away(3.0, 0.5))
    [_, trimmed] = trim_doubled_ends([line, fork], 1.0, 30.0)
    pts = trimmed.points
    assert pts[0, 1] == 0.0 and 2.0 <= pts[0, 0] <= 5.0  # starts on the line
    band = shapely.buffer(shapely.LineString(line.points), 1.0)
    def beside(p: np.ndarray) -> float:
        return float(shapely.length(shapely.intersection(shapely.LineString(p), band)))
    assert beside(fork.points) > 3.0 and beside(pts) < 2.0  # the fork, and the way out
    leaving = fork.points[fork.points[:, 0] >= 5.0]
    assert shapely.hausdorff_distance(shapely.LineString(pts[1:]),
                                      shapely.LineString(leaving)) < 0.1
    short = Edge(_along_then_away(1.0, 0.5))
    across = Edge(np.array([[5.0, -3.0], [6.0, 3.0]]))
    a = np.linspace(0, 2 * np.pi, 60)
    loop = Edge(np.column_stack([6 + 3 * np.cos(a), 3.5 + 3 * np.sin(a)]), closed=True)
    kept = trim_doubled_ends([line, short, across, loop], 1.0, 30.0)
    assert all(k.points is e.points for k, e in zip(kept, [line, short, across, loop]))


def test_of_two_strokes_overlapping_end_to_end_only_the_shorter_is_cut():
    long_ = Edge(np.column_stack([np.linspace(0, 10, 50), np.zeros(50)]))
    back = Edge(np.column_stack([np.linspace(12, 7, 30), np.full(30, 0.4)])[::-1])
    out = trim_doubled_ends([long_, back], 1.0, 30.0)
    assert out[0].points is long_.points
    assert out[1].points[:, 0].min() >= 9.0  # only what runs past the long one's end is left


def test_an_end_a_little_farther_off_is_cut_only_where_ink_fills_the_space_between():
    """reach 0.75, up to 1.0 where ink fills: a stroke 0.9 above a line for 3 units, then
    away, is cut where passes drawn between them (0.3 and 0.6 above the line) leave no gap
    wider than 0.4; with nothing between them it is two lines drawn close, and kept."""
    line = Edge(np.array([[0.0, 0.0], [20.0, 0.0]]))
    fork = Edge(_along_then_away(3.0, 0.9))
    passes = [_along_then_away(3.0, y)[:40] for y in (0.3, 0.6)]
    bare = InkFill(lines_from([line.points, fork.points]), 0.4)
    filled = InkFill(lines_from([line.points, fork.points, *passes]), 0.4)
    [_, kept] = trim_doubled_ends([line, fork], 0.75, 30.0, bare, 1.0)
    assert kept.points is fork.points
    [_, cut] = trim_doubled_ends([line, fork], 0.75, 30.0, filled, 1.0)
    assert cut.points[0, 1] == 0.0 and 2.0 <= cut.points[0, 0] <= 5.0  # starts on the line
    assert trim_doubled_ends([line, fork], 0.75, 30.0)[1].points is fork.points  # no fill


def _drawn_by_every_pair(through: DrawnThrough, x: int, y: int) -> bool:
    """DrawnThrough.drawn by its definition: some pass near probe x and some pass of the same
    stroke near probe y, within the detour, with a pass near each node between them."""
    sx, ax = through.at_probe.of(x)
    sy, ay = through.at_probe.of(y)
    nx, ny = int(through.end_node[x]), int(through.end_node[y])
    way = through.way[x] + np.hypot(*(through.nodes[nx] - through.nodes[ny])) + through.way[y]
    reach = THROUGH_DETOUR * way + 2 * through.radius
    for i in range(len(sx)):
        for j in range(len(sy)):
            lo, hi = sorted((ax[i], ay[j]))
            if sx[i] != sy[j] or hi - lo > reach:
                continue
            if all(((sn == sx[i]) & (an >= lo) & (an <= hi)).any()
                   for sn, an in (through.at_node.of(n) for n in {nx, ny})):
                return True
    return False


def _random_rows(rng, points: int, lengths: np.ndarray, most: int) -> InkRows:
    """Rows as NearestInk.passing gives them: running arc lengths, a gap of 1 between
    strokes."""
    offsets = np.concatenate([[0.0], np.cumsum(lengths + 1.0)[:-1]])
    counts = rng.integers(0, most + 1, points)
    stroke = rng.integers(0, len(lengths), counts.sum())
    at = offsets[stroke] + rng.uniform(0, 1, len(stroke)) * lengths[stroke]
    return InkRows(np.concatenate([[0], np.cumsum(counts)]), stroke, at)


def test_a_stroke_drawn_through_a_junction_is_found_as_by_comparing_every_pair_of_passes():
    rng = np.random.default_rng(3)
    found = 0
    for _ in range(3000):
        lengths = rng.uniform(0.01, 0.3, rng.integers(1, 4))
        way = rng.uniform(0, rng.choice([0.1, 1.0]), 6)  # a detour past the next stroke too
        through = DrawnThrough(way, rng.integers(0, 3, 6),
                               rng.uniform(0, 0.1, (3, 2)), _random_rows(rng, 6, lengths, 5),
                               _random_rows(rng, 3, lengths, 5), rng.uniform(0.005, 0.05))
        x, y = rng.choice(6, 2, replace=False)
        expected = _drawn_by_every_pair(through, x, y)
        assert through.drawn(x, y) == expected
        found += expected
    assert 500 < found < 2500  # both answers are tried often


def test_thousands_of_passes_near_a_junction_take_little_memory():
    """Found in CI: a 100,000-point stroke gives tens of thousands of rows near one probe,
    and comparing every row with every row took gigabytes."""
    n = 5_000  # rows of one densely sampled stroke near each probe and node
    rows = InkRows(np.array([0, n, 2 * n]), np.zeros(2 * n, dtype=int),
                   np.concatenate([np.linspace(0.0, 0.1, n), np.linspace(0.4, 0.5, n)]))
    node = InkRows(np.array([0, n]), np.zeros(n, dtype=int), np.linspace(0.2, 0.3, n))
    through = DrawnThrough(np.array([0.1, 0.1]), np.array([0, 0]), np.zeros((1, 2)),
                           rows, node, 0.05)
    tracemalloc.start()
    try:
        assert through.drawn(0, 1)  # from 0.1 to 0.4 is within 1.5 * 0.2 + 0.1
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 10e6, peak  # every pair: arrays of 5,000 squared, 25 million items each
