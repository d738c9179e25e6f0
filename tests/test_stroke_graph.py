"""The output graph: edge ends snapped into nodes, without chaining along close lines."""

from __future__ import annotations

import numpy as np

from core.arrays.components import cluster_labels, tight_cluster_labels
from core.output.stroke_graph import Edge, build_graph


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
