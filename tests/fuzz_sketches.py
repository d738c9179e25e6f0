"""Random and adversarial sketches for fuzzing ``core.simplify`` (hypothesis strategies).

``KINDS`` maps a kind of trouble to a strategy of stroke lists; ``check`` runs one sketch
through the base complex and the simplification and asserts what must hold whatever the
input: a result or a :class:`SketchError`, never another exception; Euler's formula and
every curve bordering at most two patches on the complex; finite output inside the
input's reach. ``tests/test_fuzz.py`` runs a few examples of each kind, ``scripts/fuzz.py``
(``make fuzz``) thousands.
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from core import SimplifyParams, Sketch, SketchError, Stroke, simplify
from core.complex.base_complex import BaseComplex, check_euler
from core.io.cleaning import MIN_STROKE_SHARE

finite = st.floats(-100, 100, allow_nan=False, allow_infinity=False)
point = st.tuples(finite, finite)
polyline = st.lists(point, min_size=2, max_size=8).map(np.array)
angle = st.floats(0, 2 * np.pi, allow_nan=False)


def _segment(centre, direction, half: float) -> np.ndarray:
    d = np.array([np.cos(direction), np.sin(direction)])
    return np.array([centre - half * d, centre + half * d])


def _circle(centre, radius: float, n: int = 24) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, n)
    return np.asarray(centre) + radius * np.stack([np.cos(t), np.sin(t)], axis=1)


single_points = st.lists(
    st.one_of(point.map(lambda p: np.array([p])),  # one point
              st.tuples(point, st.integers(2, 5)).map(lambda a: np.array([a[0]] * a[1])),
              polyline),  # and some ordinary ones around them
    min_size=1, max_size=10)

repeated = st.tuples(polyline, st.integers(2, 12), st.lists(polyline, max_size=3)).map(
    lambda a: [a[0].copy() for _ in range(a[1])] + a[2])

collinear = st.lists(st.tuples(st.floats(-50, 50), st.floats(0.1, 60)), min_size=2,
                     max_size=10).map(
    lambda spans: [np.array([[x, 2 * x + 1], [x + w, 2 * (x + w) + 1]]) for x, w in spans])

star = st.tuples(point, st.lists(angle, min_size=2, max_size=24),
                 st.floats(0.5, 50)).map(
    lambda a: [_segment(np.array(a[0]), t, a[2]) for t in a[1]])

tangent_circles = st.tuples(point, st.floats(1, 40), st.lists(angle, min_size=1, max_size=6),
                            st.floats(0.2, 3)).map(
    lambda a: [_circle(a[0], a[1])] + [
        _circle(np.array(a[0]) + (a[1] + a[1] * a[3]) * np.array([np.cos(t), np.sin(t)]),
                a[1] * a[3]) for t in a[2]])

near_parallel = st.tuples(polyline, st.integers(2, 6), st.sampled_from([1e-12, 1e-9, 1e-6])
                          ).map(lambda a: [a[0] + [0.0, k * a[2]] for k in range(a[1])])

scribble = st.tuples(point, angle, st.integers(3, 40), st.floats(1, 60)).map(
    lambda a: [np.array(a[0]) + np.outer(np.resize([0.0, 1.0], a[2]) * a[3]
                                         + np.linspace(0, 1e-3, a[2]),
                                         [np.cos(a[1]), np.sin(a[1])])])

extreme_scale = st.tuples(st.lists(polyline, min_size=1, max_size=6),
                          st.sampled_from([1e-9, 1e-6, 1e6, 1e9]),
                          st.sampled_from([0.0, 1e9, -1e9, 1e-9])).map(
    lambda a: [p * a[1] + a[2] for p in a[0]])

far_ink = st.tuples(st.lists(polyline, min_size=1, max_size=4),
                    st.sampled_from([1e6, 1e9, 1e12]), st.sampled_from([1e-9, 1.0, 1e9]),
                    st.booleans()).map(
    lambda a: ([p * 1e-9 for p in a[0]] if a[3] else a[0])
    + [np.array([[a[1], 0.0], [a[1] + a[2], 0.0]]), np.array([[a[1], 1.0], [a[1] + a[2], 2.0]])])

non_finite = st.tuples(st.lists(polyline, min_size=1, max_size=6),
                       st.lists(st.tuples(st.integers(0, 100), st.integers(0, 1),
                                          st.sampled_from([np.nan, np.inf, -np.inf])),
                                min_size=1, max_size=8)).map(
    lambda a: _poison(a[0], a[1]))

long_stroke = st.tuples(st.integers(0, 2**32 - 1), st.sampled_from([20_000, 100_000]),
                        st.floats(1, 40)).map(lambda a: [_spiral(*a)])


def _spiral(rng_seed: int, n: int, turns: float) -> np.ndarray:
    """A densely drawn, slightly shaky spiral: many points, few crossings (the shake is a
    fifth of the point spacing; a shake wider than the spacing is a scribble, and one of
    100,000 points crosses itself too often to be drawn: see test_fuzz)."""
    t = np.linspace(0.05, 1, n)
    spacing = np.pi * turns / n
    shake = np.random.default_rng(rng_seed).normal(0, 0.2 * spacing, (n, 2))
    return 100 * (t[:, None] * np.stack([np.cos(2 * np.pi * turns * t),
                                         np.sin(2 * np.pi * turns * t)], axis=1) + shake)

random_sketch = st.lists(polyline, min_size=1, max_size=14)


class OnCanvas(list):
    """Strokes with the canvas their file says they were drawn on (``width``, ``height``):
    a header may say anything, and memory must follow the ink, not the header."""

    def __init__(self, strokes: list[np.ndarray], width: float, height: float) -> None:
        super().__init__(strokes)
        self.width, self.height = width, height


def _on_canvas(strokes: list[np.ndarray], scale: float, share: float) -> OnCanvas:
    scaled = [s * scale for s in strokes]
    extent = max(float(np.ptp(np.concatenate(scaled), axis=0).max()), 1e-300)
    return OnCanvas(scaled, extent * share, extent * share)


#: a drawing at any scale on a canvas the header says is far smaller than its ink (down to
#: a millionth: an SVG viewBox of 0 0 1 1 over paths 1000 long, a .scap header of 1000 over
#: ink 1e8 across), or far larger
small_canvas = st.builds(_on_canvas, st.lists(polyline, min_size=2, max_size=10),
                         st.sampled_from([1.0, 1e3, 1e8]),
                         st.sampled_from([1e-6, 1e-3, 0.1, 10.0]))


def _poison(strokes: list[np.ndarray], where) -> list[np.ndarray]:
    out = [s.copy() for s in strokes]
    for k, axis, value in where:
        s = out[k % len(out)]
        s[k % len(s), axis] = value
    return out


#: kind -> (strategy, share of a fuzzing budget; the long stroke is costly)
KINDS = {
    "single points and zero length": (single_points, 1.0),
    "repeated identical strokes": (repeated, 1.0),
    "collinear overlaps": (collinear, 1.0),
    "star junctions": (star, 1.0),
    "tangent circles": (tangent_circles, 1.0),
    "nearly parallel": (near_parallel, 1.0),
    "back-and-forth scribbles": (scribble, 1.0),
    "coordinates at 1e9 and 1e-9": (extreme_scale, 1.0),
    "NaN and inf mixed in": (non_finite, 1.0),
    "ink far away, a billion long or tiny": (far_ink, 1.0),
    "one stroke of 100,000 points": (long_stroke, 0.01),
    "a canvas far smaller or larger than its ink": (small_canvas, 1.0),
    "random": (random_sketch, 1.0),
}


def fuzz_settings(examples: int, derandomize: bool = False) -> settings:
    """How the fuzzers run: no deadline (the long stroke takes seconds), no example
    database (each run draws afresh, unless ``derandomize``: the same examples every
    run), no health check against slow or filtered data."""
    return settings(max_examples=examples, deadline=None, database=None,
                    suppress_health_check=list(HealthCheck), derandomize=derandomize)


def check_complex(cx: BaseComplex) -> None:
    """Euler's formula, and every curve bordering at most two patches that list it."""
    check_euler(cx)
    assert cx.curve_patches.shape == (cx.num_curves, 2)
    for p, patch in enumerate(cx.patches):
        for c in patch.curves():
            assert p in cx.curve_patches[c], (p, c)


def check(strokes: list[np.ndarray], params: SimplifyParams | None = None) -> str:
    """Simplify one sketch: 'simplified' or 'refused' (a SketchError); anything else,
    an exception or a broken invariant, is a failure and raises."""
    try:
        sketch = Sketch([Stroke(s) for s in strokes], getattr(strokes, "width", None),
                        getattr(strokes, "height", None))
        result = simplify(sketch, params)
    except SketchError:
        return "refused"
    check_complex(result.complex)
    state = result.state  # the simplified complex: alive curves border only alive patches
    for c in state.alive_curves():
        assert all(p < 0 or state.patch_alive[p] for p in state.curve_sides[c]), c
    finite_in = np.concatenate([s[np.isfinite(s).all(axis=1)] for s in strokes])
    lo, hi = finite_in.min(axis=0), finite_in.max(axis=0)
    reach = max(float((hi - lo).max()), 1e-300)
    if any(np.ptp(s[np.isfinite(s).all(axis=1)], axis=0).max() > MIN_STROKE_SHARE * reach
           for s in strokes if np.isfinite(s).all(axis=1).sum() >= 2):
        assert result.strokes, "every stroke was lost"  # simplified means something came out
    for s in result.strokes:
        assert np.isfinite(s.points).all() and np.isfinite(s.bezier).all()
        # output stays where the ink was (within a tenth of its extent for the fits)
        assert (s.points >= lo - 0.1 * reach).all() and (s.points <= hi + 0.1 * reach).all()
    return "simplified"
