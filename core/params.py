"""Parameters of the simplification, with the paper's defaults, validated."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace

import numpy as np

from .arrays.geometry import Segments, tangents
from .arrays.polylines import resample_each, split, total_lengths
from .sketch import SketchError

__all__ = ["EPSILON_SOFT_MAX", "FILL_GAP_SHARE", "INK_CELL", "LOOSE_ALPHA",
           "MIN_ALPHA", "Tuning",
           "PAPER_ALPHA", "SPACING_SHARE", "STROKE_SHARE", "SWAP_SHARE", "WIDEST_ALPHA",
           "WIDE_BANDED", "WIDE_FROM", "SimplifyParams", "banded_shares", "ink_spacing"]

#: the bundle width as a fraction of the drawing's diagonal: the paper's alpha
PAPER_ALPHA = 0.012

#: "auto" alpha is this many times the ink's spacing (:func:`ink_spacing`), between
#: PAPER_ALPHA and LOOSE_ALPHA (see SimplifyParams.resolved)
SPACING_SHARE = 1.5
LOOSE_ALPHA = 0.015

#: a sparse drawing whose ink's width (SPACING_SHARE times its spacing) is at least
#: WIDE_FROM is first tried that wide, at most WIDEST_ALPHA, and the wider result kept only
#: where it keeps the ink (SimplifyParams.widths, core.simplify.KEEP_REACH)
WIDE_FROM = 0.02
WIDEST_ALPHA = 0.03

#: ... nor where more than this share of the ink lies in bands of lines that a bundle that
#: wide cannot hold (:func:`banded_shares`: hatching, a spiral's arms)
WIDE_BANDED = 0.1

#: input ink runs along a section's line where the |cos| between them is at least this
ALONG_COS = 0.9

#: a band's passes wander across each other (one loose line, not hatching) where two lie
#: over half the width to either side of each other, each side along at least this share
#: of their way together (:func:`_swapping`)
SWAP_SHARE = 0.2

#: the cells, as a fraction of the drawing's diagonal, that :func:`ink_spacing` counts
INK_CELL = 0.02

#: "auto" alpha is at most this share of the median stroke length (see resolved)
STROKE_SHARE = 0.5

#: the narrowest bundle, given or "auto": 100 snapping grids (core.complex.noding.GRID).
#: Output lines are sampled a quarter of the width apart, so a narrower one only
#: multiplies samples: a sketch of a few vanishing strokes (1e-120 of its diagonal) asked
#: for 10^112 of them by the median-length cap, and failed
MIN_ALPHA = 1e-4

#: "auto" fill_gap is the ink's spacing, at most this share of d_eps (see resolved)
FILL_GAP_SHARE = 0.7

@dataclass(frozen=True)
class Tuning:
    """The tuned constants of the line stage (:mod:`core.lines`), in one place. Lengths are
    multiples of the bundle width d_eps; each says why it is what it is. How each was
    measured is in ``docs/decisions.md``.

    cut_angle       a stroke is cut where it turns more than this (degrees) within
                    cut_reach d_eps each side: a corner drawn in one motion is two lines
    cut_reach       see cut_angle; 2: a corner drawn rounded (radius up to about 2 d_eps)
                    is a corner too
    follow_reach    a stroke's sample follows the complex's nearest alive curve within
                    this (what merges keep lies within d_eps of what they removed)
    follow_cos      ... running along it, |cos| at least this (30 degrees: the merge angle)
    shared_share    two pieces that follow the same alive curves together are one line
                    when they do along this share of the shorter one's length (summed
                    over the curves: a long stroke follows many, each cut at a crossing)
    shared_length   ... or this long
    shared_gap      ... overlapping where they follow a curve, or at most this apart
    member_share    a piece stays in its group when at least this share of it lies within
                    member_reach of the group's fitted line (else it is split off): the
                    trade-off between whole lines and doubled ones (docs/decisions.md)
    member_reach    see member_share; 1.5: a loose pass lies up to d_eps off the middle
                    (a stretch of ink farther than this from every line is made a line
                    of its own: core.lines.orphans)
    along_share     pass 5 joins two fitted lines when this share of the shorter lies
                    within d_eps of the longer, running along it (doubled passes the
                    merges left apart), where no clear band lies between their inks
    join_reach      lines pass 5 pairs are joined (and pass 6 leaves a line out for a
                    longer one) only where the joint line keeps each of them in place:
                    join_share of each within this of it; 0.5: whole lines are judged
                    within about half a bundle width, and two lines drawn close (a rim's
                    nested ellipses, a box's doubled edge) would both move to a line
                    between them
    join_share      see join_reach; 0.8: a line kept whole by the joint line, as the
                    clean-lines issue counts a whole line (80% of it within the reach)
    apart           ... or where no other line lies within this many times the farthest
                    move along half the joint line: passes of one loose line in open paper
                    (StrokeAggregator's judging against the local spacing of lines)
    bin             the centreline is fitted in bins this long along its spine ...
    smooth          ... and its offsets smoothed by a Gaussian of this sigma
    snap            an end within this of another line meets it (T and L junctions)
    overshoot       an end that crosses another line and runs on past it at most this
                    long is cut at the crossing: an overshoot, not a line drawn through
    crumb           a line shorter than this whose every point lies within absorb_reach
                    of a longer line is that line's (a hook at a stroke's end, a crumb
                    at a junction): its pieces join that line's group; so is a longer
                    one where no clear band lies between their inks (a loose pass)
    absorb_reach    see crumb; 0.75: within the bundle width, with a margin
    band_ratio      a band free of ink between two inks parts two lines where it is wider
                    than the drawing's usual spacing of passes (fill_gap), or than this
                    times the wider of the inks beside it (two tight bundles drawn close:
                    the width is local, from the ink) ...
    band_floor      ... and at least this wide (half the bundle width: two lines closer
                    than that, fitted as one between them, each lie within a quarter of
                    d_eps of it; loose passes drawn a little apart stay one line)
    """

    cut_angle: float = 70.0
    cut_reach: float = 2.0
    follow_reach: float = 1.0
    follow_cos: float = 0.866
    shared_share: float = 0.5
    shared_length: float = 2.0
    shared_gap: float = 1.0
    member_share: float = 0.5
    member_reach: float = 1.5
    along_share: float = 0.6
    join_reach: float = 0.5
    join_share: float = 0.8
    apart: float = 3.0
    bin: float = 0.25
    smooth: float = 0.5
    snap: float = 1.0
    overshoot: float = 2.0
    crumb: float = 3.0
    absorb_reach: float = 0.75
    band_ratio: float = 1.0
    band_floor: float = 0.5


#: the top of epsilon's useful range (the add-on's slider ends here; beyond it drawings
#: merge into blobs); a cached run covers it all, so that every slider position replays
EPSILON_SOFT_MAX = 0.06


@dataclass(frozen=True)
class SimplifyParams:
    """What controls :func:`core.simplify`. Distances are fractions of the diagonal D of
    the drawing: the strokes' bounding box, unless some ink lies far from the drawing (a
    stray mark, another panel, the other drawings of a page), which is then left out of D
    so that the drawing is simplified as if alone (:func:`core.io.cleaning.drawing_box`).

    epsilon       merge while the cheapest shape change (Fourier descriptor distance) is
                  below this: the one slider (paper: 0.01-0.03, default 0.015); 0 merges
                  nothing
    samples       N, boundary samples of a Fourier descriptor (paper: 256)
    alpha         the stroke bundle width d_eps = alpha * D: curves closer than this may
                  merge, and nothing merged away lies farther than this from what remains.
                  "auto" (default): measured from how far apart the drawing's ink
                  lies (:meth:`resolved`), 0.012 (the paper's) to 0.015; a sparse
                  drawing is tried up to 0.03 first, kept where its result keeps the
                  ink (:meth:`widths`). A result's params hold the number used
    angle         largest tangent angle, in degrees, between curves that may merge (d_theta)
    corner_angle  turns sharper than this, in degrees, stay corners of the fitted Beziers
    fit_error     largest distance of a fitted Bezier from its polyline, as a fraction of
                  d_eps = alpha * D (the bundle width sets how exact the fit need be)
    smoothing     each output line is smoothed between its corners, before the fit, by a
                  Gaussian of this many d_eps (0: none), so that it shows no steps where
                  it passes from one stroke of a bundle to the next
    fill_gap      the widest band free of ink that may lie inside one bundle (a fraction
                  of D): two lines whose inks leave no band free of ink wider than this
                  between them may be one line drawn twice, and are joined where their
                  joint fit keeps both (:mod:`core.lines.join`, :mod:`core.lines.absorb`).
                  "auto" (default): the ink's spacing (:func:`ink_spacing`), at most
                  :data:`FILL_GAP_SHARE` of d_eps; 0: never. A result's params hold the
                  number used
    target_patches, target_curves   optional: also stop once this few remain
    max_curves    refuse a sketch whose strokes cross into more curves than this (None: no
                  limit): the largest real sketches make about 17,000, and one of 100,000
                  takes many minutes
    skip          names of pen passes to leave out, for ablations (:data:`core.lines.PASSES`)
    tuning        the pen stage's tuned constants (:class:`Tuning`)
    """

    epsilon: float = 0.015
    samples: int = 256
    alpha: float | str = "auto"
    angle: float = 30.0
    corner_angle: float = 50.0
    fit_error: float = 1 / 6
    smoothing: float = 0.5
    fill_gap: float | str = "auto"
    target_patches: int | None = None
    target_curves: int | None = None
    max_curves: int | None = 100_000
    skip: tuple[str, ...] = ()
    tuning: Tuning = Tuning()

    def __post_init__(self) -> None:
        def check(ok: bool, message: str) -> None:
            if not ok:
                raise SketchError(f"bad parameter: {message}")

        # params travel as plain data (as_dict, JSON, a cluster's task): rebuilt from it
        if isinstance(self.tuning, dict):
            known = {f.name for f in fields(Tuning)}
            check(set(self.tuning) <= known,
                  f"unknown tuning {sorted(set(self.tuning) - known)}")
            object.__setattr__(self, "tuning", Tuning(**self.tuning))
        if isinstance(self.skip, list):
            object.__setattr__(self, "skip", tuple(self.skip))

        numbers = ("epsilon", "angle", "corner_angle",
                   "fit_error", "smoothing") + (() if self.alpha == "auto" else ("alpha",)) \
            + (() if self.fill_gap == "auto" else ("fill_gap",))
        for name in numbers:
            value = getattr(self, name)
            check(isinstance(value, (int, float)) and math.isfinite(value),
                  f"{name} must be a finite number, got {value!r}")
        check(self.epsilon >= 0, f"epsilon must be >= 0, got {self.epsilon}")
        check(0 <= self.smoothing <= 4, f"smoothing must be 0 to 4, got {self.smoothing}")
        check(isinstance(self.samples, int) and self.samples >= 8 and self.samples % 2 == 0,
              f"samples (N) must be an even integer >= 8, got {self.samples!r}")
        check(self.alpha == "auto" or MIN_ALPHA <= self.alpha <= 0.2,
              f"alpha must be 'auto' or in [{MIN_ALPHA}, 0.2], got {self.alpha!r}")
        check(self.fill_gap == "auto" or 0 <= self.fill_gap <= 0.2,
              f"fill_gap must be 'auto' or in [0, 0.2], got {self.fill_gap!r}")
        for name in ("angle", "corner_angle"):
            check(0 <= getattr(self, name) <= 180, f"{name} must be 0 to 180 degrees")
        check(0 < self.fit_error <= 1, f"fit_error must be in (0, 1], got {self.fit_error}")
        check(isinstance(self.skip, tuple) and all(isinstance(x, str) for x in self.skip),
              f"skip must be a tuple of pass names, got {self.skip!r}")
        check(isinstance(self.tuning, Tuning), "tuning must be a Tuning")
        for name in ("target_patches", "target_curves", "max_curves"):
            value = getattr(self, name)
            check(value is None or (isinstance(value, int) and value >= 0),
                  f"{name} must be a whole number >= 0 or None, got {value!r}")

    def resolved(self, unit_strokes: list[np.ndarray] | None = None) -> SimplifyParams:
        """These params with alpha and fill_gap numbers, fractions of the drawing's diagonal
        (the unit frame's, :class:`core.io.cleaning.Normalisation`): the narrowest that
        :meth:`widths` tries, the one kept whatever its result.

        "auto" follows the ink when ``unit_strokes`` (the drawing's strokes in the unit
        frame, without ink far away) are given: :data:`SPACING_SHARE` times their spacing
        (:func:`ink_spacing`), no narrower than the paper's 0.012 and no wider than
        :data:`LOOSE_ALPHA`. A sparse drawing, whose passes lie far apart for its size
        (cartoons, handwriting, test drawings), gets a wider bundle; a dense one (product
        sketches: many close construction lines) keeps the paper's. (How each bound was
        measured: ``docs/decisions.md``, "The auto width's bounds".)

        Then never more than :data:`STROKE_SHARE` of the median length of the strokes (nor
        less than :data:`MIN_ALPHA`): a bundle is never wider than half the strokes that
        make it are long. Where a drawing is many small parts spread wide, the width
        follows the parts, not the spread.

        "auto" fill_gap is the ink's spacing, at most :data:`FILL_GAP_SHARE` of d_eps
        (without strokes, that share of d_eps): a band free of ink wider than the drawing's
        usual distance between passes is the space between two lines, not a gap inside a
        bundle.

        >>> SimplifyParams().resolved().alpha, SimplifyParams(alpha=0.02).resolved().alpha
        (0.012, 0.02)
        >>> round(SimplifyParams().resolved().fill_gap, 6)  # 0.7 d_eps without strokes
        0.0084
        >>> t = np.linspace(0, 0.7, 50)[:, None]
        >>> two = [np.hstack([t, 0.3 + 0 * t]), np.hstack([t, 0.314 + 0 * t])]  # a pair
        >>> SimplifyParams().resolved(two).alpha  # sparse: the widest
        0.015
        >>> hatch = [np.hstack([t, 0.1 + 0.004 * k + 0 * t]) for k in range(60)]
        >>> SimplifyParams().resolved(hatch).alpha  # dense: the paper's
        0.012
        >>> short = [np.array([[0.0, 0.0], [0.02, 0.0]])] * 3  # strokes 2% of the diagonal
        >>> round(SimplifyParams().resolved(short).alpha, 6)
        0.01
        """
        return self._widths(unit_strokes, wider=False)[-1]

    def widths(self, unit_strokes: list[np.ndarray] | None = None) -> list[SimplifyParams]:
        """The resolved params that :func:`core.simplify` tries, widest first: the last is
        :meth:`resolved`'s (at most :data:`LOOSE_ALPHA`), kept whatever its result; before
        it, for a sparse drawing under "auto" alpha whose ink's width (:data:`SPACING_SHARE`
        times its spacing, at most :data:`WIDEST_ALPHA` and the median-length cap) is at
        least :data:`WIDE_FROM`, that width and the one halfway down to LOOSE_ALPHA, each
        unless more than :data:`WIDE_BANDED` of the ink lies in bands of lines a bundle that
        wide cannot hold (:func:`banded_shares`), and each kept only where its result keeps
        the ink (:data:`core.simplify.KEEP_REACH`).

        Why tried and checked: a loose drawing's passes lie farther apart than LOOSE_ALPHA
        (two passes 3% of the diagonal apart along a long line are one line drawn twice),
        but a fixed cap above it merged the spiral test drawings' distinct arms and lost
        their ink (kept 0.92 at 2%). Lines a width cannot hold as one bundle (hatching, a
        spiral's arms) show in the ink before trying; a result that leaves ink out shows
        after. Measured on 190 sketches: see :mod:`core.simplify`.

        >>> t = np.linspace(0, 1, 60)[:, None]
        >>> two = [np.hstack([t, 0.3 + 0 * t]), np.hstack([t, 0.33 + 0 * t])]
        >>> [round(p.alpha, 4) for p in SimplifyParams().widths(two)]  # 3% apart: sparse
        [0.03, 0.0225, 0.015]
        >>> [p.alpha for p in SimplifyParams(alpha=0.02).widths(two)]  # a number: that
        [0.02]
        >>> hatch = [np.hstack([t, 0.3 + 0.025 * k + 0 * t]) for k in range(8)]
        >>> [round(p.alpha, 4) for p in SimplifyParams().widths(hatch)]  # not merged at 3%
        [0.0225, 0.015]
        """
        return self._widths(unit_strokes, wider=True)

    def _widths(self, unit_strokes: list[np.ndarray] | None, wider: bool
                ) -> list[SimplifyParams]:
        if self.alpha != "auto" and self.fill_gap != "auto":
            return [self]
        spacing = ink_spacing(unit_strokes) if unit_strokes else None
        alphas = [self.alpha]
        if self.alpha == "auto":
            alphas = [PAPER_ALPHA]
            if unit_strokes:
                cap = STROKE_SHARE * float(np.median(total_lengths(unit_strokes)))
                wide = min(SPACING_SHARE * spacing, WIDEST_ALPHA, cap)
                alphas = [max(min(max(SPACING_SHARE * spacing, PAPER_ALPHA), LOOSE_ALPHA, cap),
                              MIN_ALPHA)]
                if wider and wide >= WIDE_FROM:
                    tries = [wide, (wide + LOOSE_ALPHA) / 2]
                    alphas = [w for w, banded in zip(tries, banded_shares(unit_strokes, tries))
                              if banded <= WIDE_BANDED] + alphas
        return [replace(self, alpha=alpha, fill_gap=self._fill_gap(alpha, spacing))
                for alpha in alphas]

    def _fill_gap(self, alpha: float, spacing: float | None) -> float:
        if self.fill_gap != "auto":
            return self.fill_gap
        fill_gap = FILL_GAP_SHARE * alpha
        return fill_gap if spacing is None else min(spacing, fill_gap)

    def as_dict(self) -> dict:
        return asdict(self)


def ink_spacing(unit_strokes: list[np.ndarray]) -> float:
    """How far apart the ink lies, in the unit frame: the area the ink occupies (cells of
    :data:`INK_CELL` holding any of it) over its length. One line through empty space
    gives about the cell size; passes drawn side by side share cells and give less; many
    close lines (a product sketch's construction lines, hatching) give much less. It
    depends on the drawing alone, not on where it lies or how big it is (the unit frame),
    and it follows the sketch's best bundle width (by the dev sketches' labels, a
    correlation of 0.56 in logs; product sketches 0.0064, median of the others 0.0105).

    >>> t = np.linspace(0, 1, 101)[:, None]
    >>> round(ink_spacing([np.hstack([t, 0.5 + 0 * t])]), 3)  # a line: its cells' width
    0.02
    """
    points, _ = resample_each(unit_strokes, INK_CELL / 8)
    length = float(total_lengths(unit_strokes).sum())
    if length <= 0:
        return 0.0
    cell = np.floor(points / INK_CELL).astype(np.int64)
    cell -= cell.min(axis=0)
    cells = len(np.unique(cell[:, 0] * (int(cell[:, 1].max()) + 1) + cell[:, 1]))
    return cells * INK_CELL ** 2 / length


def banded_shares(unit_strokes: list[np.ndarray], widths: list[float]) -> list[float]:
    """For each width: the share of the ink, in the unit frame, that a bundle that wide
    cannot hold. That is where the section square to a stroke (every quarter of the
    width, twice the width each side) meets passes running along it (within about 26
    degrees) chained by gaps of at most the width into a band wider than it, unless the
    band's passes wander across each other (:func:`_swapping`). Hatching or a spiral's arms
    closer than the width are such bands, and a width this wide would merge their lines;
    the passes of one loose line drawn over and over are not, where they span no more
    than it or cross from side to side of it.

    >>> t = np.linspace(0, 1, 101)[:, None]
    >>> two = [np.hstack([t, 0.3 + 0 * t]), np.hstack([t, 0.33 + 0 * t])]  # one line, twice
    >>> banded_shares(two, [0.03])
    [0.0]
    >>> hatch = [np.hstack([t, 0.3 + 0.025 * k + 0 * t]) for k in range(8)]
    >>> banded_shares(hatch, [0.03, 0.0225])  # chained, then apart
    [1.0, 0.0]
    >>> loose = [np.hstack([t, 0.5 + 0.02 * np.sin(2 * np.pi * (1.5 * t + k / 4))])
    ...          for k in range(4)]  # four passes wandering over a band 4% wide
    >>> banded_shares(loose, [0.03])
    [0.0]
    """
    segments = Segments.of(unit_strokes)
    return [_banded_share(unit_strokes, segments, width) for width in widths]


def _banded_share(unit_strokes: list[np.ndarray], segments: Segments, width: float) -> float:
    points, counts = resample_each(unit_strokes, width / 4)
    tangent = np.concatenate([tangents(p) for p in split(points, counts)])
    cross = segments.crossings(points, tangent, 2 * width, ALONG_COS)
    order = np.lexsort((cross.offset, cross.section))
    sec, offset, passing = cross.section[order], cross.offset[order], cross.polyline[order]
    if not len(sec):
        return 0.0
    first = np.ones(len(sec), dtype=bool)  # each chain's first crossing
    first[1:] = (sec[1:] != sec[:-1]) | (np.diff(offset) > width)
    chain = np.cumsum(first) - 1
    begins = np.flatnonzero(first)
    span = (np.maximum.reduceat(offset, begins) - np.minimum.reduceat(offset, begins))[chain]
    # each section's own chain: the one through its crossing nearest the middle
    nearest = np.full(len(points), np.inf)
    np.minimum.at(nearest, sec, np.abs(offset))
    own = np.abs(offset) == nearest[sec]
    own_chain = np.full(len(points), -1)
    own_chain[sec[own]] = chain[own]
    banded = np.zeros(len(points), dtype=bool)
    banded[sec[own]] = span[own] > width
    in_band = chain == own_chain[sec]
    owner = np.repeat(np.arange(len(counts)), counts)
    banded[_swapping(owner[sec[in_band]], passing[in_band], offset[in_band], sec[in_band],
                     width)] = False
    return float(banded.mean())


def _swapping(owner: np.ndarray, passing: np.ndarray, offset: np.ndarray,
              section: np.ndarray, width: float) -> np.ndarray:
    """The sections, among those given, where another stroke in the band lies more than
    half the width to one side of the section's stroke along at least :data:`SWAP_SHARE`
    of the sections where they run together, and as far to the other side along as much.

    The passes of one loose line drawn over and over wander across each other and across
    its middle; hatching's lines and a spiral's arms keep their sides, each pass of a
    hatch line drawn twice stays within its line, and neighbours crossing near their ends
    swap along less than a fifth of their way (measured on test drawings of each: see
    tests/test_simplify.py).

    Args:
        owner, passing: (k,) per crossing in a band, the stroke of its section and the
            stroke crossing it.
        offset: (k,) the crossing's signed distance from the section's middle.
        section: (k,) the crossing's section.
        width: the bundle width tried.

    Returns:
        The sections (indices into the sections, possibly repeated) whose band swaps.
    """
    other = passing != owner
    pair = owner[other].astype(np.int64) * (int(passing.max(initial=0)) + 1) + passing[other]
    if not len(pair):
        return np.zeros(0, dtype=np.intp)
    _, group = np.unique(pair, return_inverse=True)
    side = offset[other] / (width / 2)
    below = np.bincount(group, side <= -1)
    above = np.bincount(group, side >= 1)
    swaps = np.minimum(below, above) >= SWAP_SHARE * np.bincount(group)
    return section[other][swaps[group]]
