"""The simplified complex as merges change it: which curves and patches are left.

This is the light part of agglomeration, enough to replay a recorded merge history (the
slider) without any shape measurement: alive flags, each curve's patches, each patch's
boundary curves, and the polylines of curves made by curve-curve merges.

A curve is *free* when no patch lies on one side of it and another patch (or no patch) on
the other: it bounds nothing. Dangling curves inside a patch are free too.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from .base_complex import BaseComplex

__all__ = ["ComplexState", "Merge", "MergeKind"]


class MergeKind(StrEnum):
    """The three kinds of merge (paper 3.2.2); each compares equal to its two letters."""

    PP = "PP"  #: two patches sharing a curve become one
    CP = "CP"  #: a free curve touching a patch is merged away into the patch's outline
    CC = "CC"  #: two free curves side by side or end to end become one curve


@dataclass(frozen=True)
class Merge:
    """One applied merge, of a :class:`MergeKind`.

    PP: patches ``first`` and ``second`` became patch ``result``; the curves between them
    were removed. CP: curve ``first`` was merged away into patch ``second`` (``result``).
    CC: curves ``first`` and ``second`` became curve ``result`` with polyline ``points``.
    """

    kind: MergeKind
    cost: float
    first: int
    second: int
    result: int
    points: np.ndarray | None = field(default=None, compare=False)


class ComplexState:
    """Alive curves and patches of a base complex after some merges."""

    def __init__(self, cx: BaseComplex) -> None:
        self.base = cx
        n_curves, n_patches = cx.num_curves, cx.num_patches
        self.curves: list[np.ndarray] = list(cx.curves)
        self.curve_alive: list[bool] = [True] * n_curves
        self.curve_weight: list[float] = [1.0] * n_curves
        self.curve_nodes: list[frozenset[int]] = [frozenset(r) for r in cx.curve_nodes.tolist()]
        self.curve_sides: list[tuple[int, int]] = [tuple(r) for r in cx.curve_patches.tolist()]
        self.node_curves: list[set[int]] = [set(c) for c in cx.node_curves]
        self.patch_alive: list[bool] = [True] * n_patches
        self.patch_curves: list[set[int]] = [set() for _ in range(n_patches)]
        self.patch_inner: list[set[int]] = [set() for _ in range(n_patches)]  # dangling inside
        self.patch_origin: list[tuple[int, ...]] = [(p,) for p in range(n_patches)]
        for c, (a, b) in enumerate(self.curve_sides):
            if a != b:
                for p in (a, b):
                    if p >= 0:
                        self.patch_curves[p].add(c)
            elif a >= 0:
                self.patch_inner[a].add(c)
        self.merges_applied = 0
        self._num_curves, self._num_patches = n_curves, n_patches  # alive, kept up to date

    # -- queries ----------------------------------------------------------------------
    def is_base_curve(self, curve: int) -> bool:
        """Whether the curve is one of the base complex's (not made by a curve merge)."""
        return curve < self.base.num_curves

    def is_free(self, curve: int) -> bool:
        a, b = self.curve_sides[curve]
        return a == b or (a < 0 and b < 0)

    def alive_curves(self) -> list[int]:
        return [c for c, ok in enumerate(self.curve_alive) if ok]

    def alive_patches(self) -> list[int]:
        return [p for p, ok in enumerate(self.patch_alive) if ok]

    @property
    def num_curves(self) -> int:
        return self._num_curves

    @property
    def num_patches(self) -> int:
        return self._num_patches

    def targets_reached(self, patches: int | None, curves: int | None) -> bool:
        """Whether no more than ``patches`` patches or ``curves`` curves are left (None:
        no such target): where a run with targets stops, and so its replay."""
        return ((patches is not None and self._num_patches <= patches)
                or (curves is not None and self._num_curves <= curves))

    def shared_curves(self, p: int, q: int) -> list[int]:
        small, large = sorted((self.patch_curves[p], self.patch_curves[q]), key=len)
        return sorted(c for c in small if c in large)

    def patches_at_node(self, node: int) -> set[int]:
        """Alive patches with a boundary curve ending at ``node``."""
        out: set[int] = set()
        for c in self.node_curves[node]:
            if self.curve_alive[c] and not self.is_free(c):
                out.update(p for p in self.curve_sides[c] if p >= 0)
        return out

    # -- edits --------------------------------------------------------------------------
    def _kill_curve(self, c: int) -> None:
        self.curve_alive[c] = False
        self._num_curves -= 1
        for n in self.curve_nodes[c]:
            self.node_curves[n].discard(c)
        a, b = self.curve_sides[c]
        if a == b and a >= 0:
            self.patch_inner[a].discard(c)

    def merge_patches(self, p: int, q: int) -> int:
        """Union of two adjacent patches; the curves between them are removed."""
        r = len(self.patch_alive)
        shared = self.patch_curves[p] & self.patch_curves[q]
        curves = self.patch_curves[p] ^ self.patch_curves[q]
        for c in shared:
            self._kill_curve(c)
        for c in curves:
            a, b = self.curve_sides[c]
            self.curve_sides[c] = (r if a in (p, q) else a, r if b in (p, q) else b)
        inner = self.patch_inner[p] | self.patch_inner[q]
        for c in inner:  # dangling curves inside p or q stay inside r
            self.curve_sides[c] = (r, r)
        self.patch_alive[p] = self.patch_alive[q] = False
        self.patch_alive.append(True)
        self._num_patches -= 1
        self.patch_curves.append(curves)
        self.patch_inner.append(inner)
        self.patch_origin.append(self.patch_origin[p] + self.patch_origin[q])
        return r

    def remove_curve(self, c: int) -> None:
        """Curve-patch merge: the free curve is absorbed by the patch it touches."""
        self._kill_curve(c)

    def merge_curves(self, a: int, b: int, points: np.ndarray) -> int:
        """Two free curves become one, drawn along ``points``."""
        n = len(self.curves)
        self._kill_curve(a)
        self._kill_curve(b)
        nodes = self.curve_nodes[a] | self.curve_nodes[b]
        sa, sb = self.curve_sides[a], self.curve_sides[b]
        inside = sa[0] if sa == sb else -1  # both dangling inside one patch: stay inside
        self.curves.append(points)
        self.curve_alive.append(True)
        self._num_curves += 1
        self.curve_weight.append(self.curve_weight[a] + self.curve_weight[b])
        self.curve_nodes.append(nodes)
        self.curve_sides.append((inside, inside))
        for node in nodes:
            self.node_curves[node].add(n)
        if inside >= 0:
            self.patch_inner[inside].add(n)
        return n

    def apply(self, merge: Merge) -> int:
        """Apply a recorded merge; returns the id of what it made (or kept)."""
        self.merges_applied += 1
        if merge.kind == MergeKind.PP:
            return self.merge_patches(merge.first, merge.second)
        if merge.kind == MergeKind.CP:
            self.remove_curve(merge.first)
            return merge.second
        if merge.kind == MergeKind.CC:
            return self.merge_curves(merge.first, merge.second, merge.points)
        raise ValueError(f"unknown merge kind {merge.kind!r}")
