"""Parts of the agglomeration checked against slower, obvious versions of themselves."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from core import build_base_complex
from core.arrays.geometry import lines_from
from core.complex.complex_state import ComplexState
from core.complex.patch_rings import (
    Outline,
    RingGeometry,
    half_edges,
    union_outline_points,
    union_rings,
)
from core.merge.agglomeration import Agglomerator
from core.merge.guard import DistanceGuard
from core.params import SimplifyParams


def grid(n: int = 4, wobble: float = 0.0, seed: int = 0) -> list[np.ndarray]:
    """n + 1 horizontal and n + 1 vertical overshooting lines: n * n square faces."""
    rng = np.random.default_rng(seed)
    t = np.linspace(-0.05, 1.05, 30)
    lines = []
    for k in np.linspace(0, 1, n + 1):
        off = wobble * rng.normal(size=len(t))
        lines.append(np.stack([t, k + off], axis=1))
        lines.append(np.stack([k + off, t], axis=1))
    return lines


@pytest.mark.parametrize("wobble", [0.0, 0.01])
def test_quick_union_outline_equals_the_general_union(wobble):
    cx = build_base_complex(grid(4, wobble))
    geometry = RingGeometry(cx)
    state = ComplexState(cx)
    rings = [[half_edges(p.boundary)] + [half_edges(h) for h in p.holes] for p in cx.patches]
    checked = 0
    for p in range(cx.num_patches):
        for q in range(p + 1, cx.num_patches):
            shared = state.shared_curves(p, q)
            if not shared:
                continue
            quick = union_outline_points(Outline(rings[p][0], geometry),
                                         Outline(rings[q][0], geometry), shared)
            general = geometry.points(union_rings(rings[p], rings[q], shared, geometry)[0])
            assert quick is not None
            a, b = shapely.Polygon(quick), shapely.Polygon(general)
            assert a.is_valid and a.area == pytest.approx(b.area)
            assert a.equals(b)
            checked += 1
    assert checked == 2 * 4 * 3  # every pair of faces side by side


def test_union_of_patches_sharing_two_runs_leaves_a_hole():
    # a ring of four faces around a central one: merging two opposite halves that meet
    # on both sides encloses the centre
    outer = np.array([[0, 0], [3, 0], [3, 3], [0, 3], [0, 0]], float)
    inner = np.array([[1, 1], [2, 1], [2, 2], [1, 2], [1, 1]], float)
    cut = [np.array([[1.5, -0.5], [1.5, 1]]), np.array([[1.5, 2], [1.5, 3.5]])]
    cx = build_base_complex([outer, inner, *cut])
    geometry = RingGeometry(cx)
    state = ComplexState(cx)
    rings = [[half_edges(p.boundary)] + [half_edges(h) for h in p.holes] for p in cx.patches]
    halves = [p for p in range(cx.num_patches) if cx.patches[p].area > 1.5]
    assert len(halves) == 2
    p, q = halves
    shared = state.shared_curves(p, q)
    assert union_outline_points(Outline(rings[p][0], geometry), Outline(rings[q][0], geometry),
                                shared) is None  # two runs: the quick path declines
    united = union_rings(rings[p], rings[q], shared, geometry)
    assert len(united) == 2  # an outer ring and the hole around the centre
    assert geometry.area(united[0]) == pytest.approx(9.0)
    assert geometry.area(united[1]) == pytest.approx(-1.0)


def brute_covered(samples, curves, removed, allowed, d_eps):
    pts = np.concatenate([samples[c] for c in removed])
    line = shapely.union_all(lines_from([curves[c] for c in allowed]))
    return shapely.distance(shapely.points(pts), line).max() <= d_eps


@pytest.mark.parametrize("seed", range(5))
def test_guard_agrees_with_brute_force(seed):
    rng = np.random.default_rng(seed)
    curves = [np.cumsum(rng.normal(0, 0.01, (12, 2)), axis=0) + rng.uniform(0, 0.1, 2)
              for _ in range(25)]
    d_eps = 0.02
    unconnected = np.arange(50).reshape(25, 2)  # each curve its own two end nodes
    guard = DistanceGuard(curves, lines_from(curves), d_eps, unconnected,
                          [[c] for c in range(25) for _ in range(2)], d_eps)
    for _ in range(60):
        removed = sorted(rng.choice(25, size=rng.integers(1, 3), replace=False).tolist())
        allowed = set(rng.choice(25, size=rng.integers(1, 6), replace=False).tolist())
        allowed -= set(removed)
        if not allowed:
            continue
        expected = brute_covered(guard.samples, curves, removed, allowed, d_eps)
        assert guard.covered(removed, allowed) == expected


@pytest.mark.parametrize("seed", range(3))
def test_guard_agrees_with_brute_force_on_crumbs_between_crossings(seed):
    """Curves of a real complex: many shorter than d_eps, settled through their end nodes."""
    rng = np.random.default_rng(seed)
    strokes = [np.cumsum(rng.normal(0, 0.05, (10, 2)), axis=0) + rng.uniform(0, 0.3, 2)
               for _ in range(12)]
    cx = build_base_complex(strokes)
    d_eps = 0.02
    guard = DistanceGuard(cx.curves, lines_from(cx.curves), d_eps, cx.curve_nodes,
                          cx.node_curves, d_eps)
    assert guard.short.sum() > 5
    n, verdicts = cx.num_curves, []
    for _ in range(80):
        removed = sorted(rng.choice(n, size=rng.integers(1, 3), replace=False).tolist())
        allowed = set(rng.choice(n, size=rng.integers(1, 8), replace=False).tolist())
        if rng.random() < 0.5:  # the curves through one end of a removed one
            allowed |= set(cx.node_curves[cx.curve_nodes[removed[0], 0]])
        allowed -= set(removed)
        if not allowed:
            continue
        expected = brute_covered(guard.samples, cx.curves, removed, allowed, d_eps)
        assert guard.covered(removed, allowed) == expected
        verdicts.append(expected)
    assert any(verdicts) and not all(verdicts)


def test_each_curves_cover_is_every_curve_near_all_its_samples():
    """Covers come from the end points' neighbours (shared between curves) and a check of
    the samples between: the same as measuring every sample against every curve."""
    rng = np.random.default_rng(7)
    strokes = [np.cumsum(rng.normal(0, 0.03, (15, 2)), axis=0) + rng.uniform(0, 0.2, 2)
               for _ in range(15)]
    cx = build_base_complex(strokes)
    d_eps = 0.02
    lines = lines_from(cx.curves)
    guard = DistanceGuard(cx.curves, lines, d_eps, cx.curve_nodes, cx.node_curves, d_eps)
    sizes = []
    for c in range(cx.num_curves):
        pts = shapely.points(guard.samples[c])
        near_all = shapely.dwithin(pts[:, None], lines[None, :], d_eps).all(axis=0)
        near_all[c] = False
        assert guard.cover(c).tolist() == np.flatnonzero(near_all).tolist()
        sizes.append(len(guard.samples[c]))
    assert min(sizes) == 2 and max(sizes) > 3  # crumbs and longer curves both seen


@pytest.mark.parametrize("seed", range(3))
def test_the_agglomerations_guard_measures_at_its_reach_and_samples_at_the_bundle_width(seed):
    """The merge loop's guard reaches ``tuning.guard_reach`` d_eps: it agrees with the brute
    force at that reach, samples the curves as at d_eps (where curve-curve pairing shares them), and
    lets fewer removals through than a guard reaching d_eps."""
    rng = np.random.default_rng(seed)
    strokes = [np.cumsum(rng.normal(0, 0.05, (10, 2)), axis=0) + rng.uniform(0, 0.3, 2)
               for _ in range(12)]
    cx = build_base_complex(strokes)
    params = SimplifyParams(alpha=0.02).resolved()
    guard = Agglomerator(cx, params).guard
    reach = params.tuning.guard_reach * params.alpha
    assert guard.reach == reach
    wide = DistanceGuard(cx.curves, lines_from(cx.curves), params.alpha, cx.curve_nodes,
                         cx.node_curves, params.alpha)
    n, narrow_ok, wide_ok = cx.num_curves, [], []
    for _ in range(80):
        removed = sorted(rng.choice(n, size=rng.integers(1, 3), replace=False).tolist())
        allowed = set(rng.choice(n, size=rng.integers(1, 8), replace=False).tolist())
        allowed |= set(cx.node_curves[cx.curve_nodes[removed[0], 0]])
        allowed -= set(removed)
        if not allowed:
            continue
        assert all(len(guard.samples[c]) == len(wide.samples[c]) for c in removed)
        expected = brute_covered(guard.samples, cx.curves, removed, allowed, reach)
        assert guard.covered(removed, allowed) == expected
        narrow_ok.append(expected)
        wide_ok.append(wide.covered(removed, allowed))
    assert not any(a and not b for a, b in zip(narrow_ok, wide_ok))  # narrower: a subset
    assert sum(narrow_ok) < sum(wide_ok)
