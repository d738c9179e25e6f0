"""What the merge loop keeps of the shape of each alive primitive (paper 3.2.1).

Patches: their rings as half-edges over the base curves (outer first), the outline used by
the quick union, and the outer ring's Fourier descriptor. Curves: their samples for pairing
(:class:`core.merge.curve_merge.SampledCurve`) and their descriptor as a slender ring.

The rule for every store here: filled on first use (or, for the base patches'
descriptors, in batches when the queue is first filled), dropped by ``forget`` when the
primitive merges away; never changed in place. A value depends only on its primitive's
shape, which never changes (a merge makes a new id), so keeping it changes no result.
"""

from __future__ import annotations

import math

import numpy as np

from ..complex.base_complex import BaseComplex
from ..complex.complex_state import ComplexState
from ..complex.patch_rings import Outline, RingGeometry, half_edges
from .curve_merge import SampledCurve, sample_spacing
from .fourier import curve_descriptors, fourier_descriptors
from .guard import DistanceGuard

__all__ = ["CurveShapes", "PatchShapes"]


class PatchShapes:
    """Rings, outlines and descriptors of the alive patches."""

    def __init__(self, cx: BaseComplex, geometry: RingGeometry, samples: int) -> None:
        self.geometry = geometry
        self.samples = samples
        #: rings of every patch, base and merged, by id; emptied when it merges away
        self.rings: list[list[list[int]]] = [
            [half_edges(p.boundary)] + [half_edges(h) for h in p.holes] for p in cx.patches]
        self._outlines: dict[int, Outline] = {}
        self._fd: dict[int, np.ndarray] = {}

    def add(self, p: int, rings: list[list[int]]) -> None:
        """The rings of merged patch ``p``: the next id, as the complex state hands them
        out (:meth:`core.complex.complex_state.ComplexState.merge_patches`)."""
        if p != len(self.rings):
            raise ValueError(f"patch {p} out of order: the next id is {len(self.rings)}")
        self.rings.append(rings)

    def outer_points(self, p: int) -> np.ndarray:
        return self.geometry.points(self.rings[p][0])

    def size(self, p: int) -> float:
        """Linear size of a patch: the square root of its outer ring's area."""
        return math.sqrt(max(self.geometry.area(self.rings[p][0]), 0.0))

    def outline(self, p: int) -> Outline:
        if p not in self._outlines:
            self._outlines[p] = Outline(self.rings[p][0], self.geometry)
        return self._outlines[p]

    def fd(self, p: int) -> np.ndarray:
        """The Fourier descriptor of the patch's outer ring."""
        if p not in self._fd:
            self._fd[p] = fourier_descriptors([self.outer_points(p)], self.samples)[0]
        return self._fd[p]

    def describe_all(self, batch: int) -> None:
        """Describe every patch so far, ``batch`` rings at a time (a batch of 256 rings
        takes about 1 MB of samples)."""
        for k in range(0, len(self.rings), batch):
            fds = fourier_descriptors([self.outer_points(p) for p in
                                       range(k, min(k + batch, len(self.rings)))], self.samples)
            self._fd.update(zip(range(k, k + len(fds)), fds))

    def forget(self, p: int) -> None:
        """Drop what is kept of a patch that merged away."""
        self.rings[p] = []
        self._outlines.pop(p, None)
        self._fd.pop(p, None)


class CurveShapes:
    """Samples and descriptors of the alive curves, base and merged."""

    def __init__(self, state: ComplexState, guard: DistanceGuard, d_eps: float,
                 samples: int) -> None:
        self.state = state
        self.guard = guard
        self.spacing = sample_spacing(d_eps)
        self.samples = samples
        self._sampled: dict[int, SampledCurve] = {}
        self._fd: dict[int, np.ndarray] = {}

    def sampled(self, c: int) -> SampledCurve:
        if c not in self._sampled:
            self.sample([c])
        return self._sampled[c]

    def sample(self, curves: list[int]) -> None:
        """Sample the curves not sampled yet, together. A base curve takes the samples the
        guard made of it alike; a merged curve is resampled."""
        missing = sorted({c for c in curves if c not in self._sampled})
        base = [c for c in missing if self.state.is_base_curve(c)]
        new = [c for c in missing if not self.state.is_base_curve(c)]
        self._sampled.update(zip(base, SampledCurve.many([self.guard.samples[c]
                                                          for c in base])))
        self._sampled.update(zip(new, SampledCurve.many([self.state.curves[c] for c in new],
                                                        self.spacing)))

    def fd(self, c: int) -> np.ndarray:
        """The Fourier descriptor of the curve as a slender ring."""
        if c not in self._fd:
            self.describe([c])
        return self._fd[c]

    def describe(self, curves: list[int]) -> None:
        """Describe the curves not yet described, in one batch (rows copied out of it, so
        that a curve merged away frees its own row only)."""
        missing = sorted({c for c in curves if c not in self._fd})
        if missing:
            fds = curve_descriptors([self.state.curves[c] for c in missing], self.samples)
            self._fd.update((c, row.copy()) for c, row in zip(missing, fds))

    def forget(self, c: int) -> None:
        """Drop what is kept of a curve that merged away (its samples and their points as
        geometries are the bulk of a dense sketch's memory)."""
        self._sampled.pop(c, None)
        self._fd.pop(c, None)
