"""Parameters of the simplification, with the paper's defaults, validated."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace

import numpy as np

from .arrays.geometry import Segments, tangents
from .arrays.polylines import resample_each, split, total_lengths
from .sketch import SketchError

__all__ = ["EPSILON_SOFT_MAX", "MIN_ALPHA", "PAPER_ALPHA", "ResolvedParams", "SimplifyParams",
           "Tuning",
           "banded_shares", "ink_spacing"]

#: the bundle width as a fraction of the drawing's diagonal: the paper's alpha
PAPER_ALPHA = 0.012

#: the narrowest bundle, given or "auto": 100 snapping grids (core.complex.noding.GRID).
#: Output lines are sampled a quarter of the width apart, so a narrower one only
#: multiplies samples: a sketch of a few vanishing strokes (1e-120 of its diagonal) asked
#: for 10^112 of them by the median-length cap, and failed
MIN_ALPHA = 1e-4


@dataclass(frozen=True)
class Tuning:
    """The tuned numbers of the pipeline, in one place. Each field's ``#:`` comment says
    what it decides and, after ``decisions:``, names the entry of ``docs/decisions.md``
    that measured it ("Where each tuned number comes from": those set by reasoning). D:
    a fraction of the drawing's diagonal; d_eps: the bundle width. Each field has one
    purpose, read by the passes named.

    Left with the code they bound: resource and precision limits (memo sizes, chunks,
    the snapping grid, file caps, :data:`MIN_ALPHA`), the paper's own values
    (:data:`PAPER_ALPHA`, the Fourier samples), the drawing frame every fraction of D is
    of (:mod:`core.io.cleaning`), and Stable Across Frames (:mod:`core.stable`), a pass
    between a shot's drawings.
    """

    # -- the width "auto" gives (SimplifyParams.resolved and widths) --
    #: alpha is this many times the ink's spacing (:func:`ink_spacing`), from
    #: narrowest_alpha to loose_alpha. decisions: "The auto width's bounds"
    spacing_share: float = 1.5
    #: the narrowest alpha (D) "auto" gives, half the paper's: a dense drawing's close
    #: lines kept apart, its lines' samples (a quarter of the width apart) bounded.
    #: decisions: "the width follows dense ink below the paper's"
    narrowest_alpha: float = PAPER_ALPHA / 2
    #: the widest alpha (D) kept whatever its result. decisions: "The auto width's bounds"
    loose_alpha: float = 0.015
    #: an ink this wide (D, spacing_share times its spacing) or wider is first tried that
    #: wide ... decisions: "Wider where the ink allows"
    wide_from: float = 0.02
    #: ... up to this (D), each try kept where it keeps the ink (keep_*). decisions:
    #: "Wider where the ink allows"
    widest_alpha: float = 0.03
    #: ... unless over this share of the ink lies in bands a bundle that wide cannot hold
    #: (:func:`banded_shares`: hatching). decisions: "Wider where the ink allows"
    wide_banded: float = 0.1
    #: a pass crossing a section runs along its stroke at |cos| at least this
    #: (:func:`banded_shares`). decisions: "Wider where the ink allows"
    band_cos: float = 0.9
    #: a band's passes wander across each other (one loose line) where each lies over half
    #: the width to both sides of the other along this share of their way. decisions:
    #: "Wider where the ink allows"
    swap_share: float = 0.2
    #: the cells (D) :func:`ink_spacing` counts. decisions: "The auto width's bounds"
    ink_cell: float = 0.02
    #: alpha is at most this share of the median stroke's length. decisions: "Where each
    #: tuned number comes from"
    stroke_share: float = 0.5
    #: "auto" fill_gap is the ink's spacing, at most this share of d_eps. decisions: "the
    #: pen stage's join keeps each line whole"
    fill_gap_share: float = 0.7

    # -- a wider width's result kept (core.simplify) --
    #: kept where at most keep_left of the ink lies farther than this (D, or of the
    #: canvas's diagonal if smaller) from it. decisions: "Wider where the ink allows"
    keep_reach: float = 0.02
    #: see keep_reach. decisions: "Wider where the ink allows"
    keep_left: float = 0.01
    #: ... nor this share of one stroke (a stem, a tick trimmed as a spur). decisions:
    #: "Wider where the ink allows"
    keep_stroke: float = 0.1

    # -- the merge (core.merge, paper 3.2) --
    #: what a merge removes lies within this many d_eps of what stays
    #: (:mod:`core.merge.guard`). decisions: "Where each tuned number comes from"
    guard_reach: float = 0.25
    #: a curve-curve pair is side by side where this share of the shorter lies within d_eps
    #: of the longer (paper 3.2.2). decisions: "Where each tuned number comes from"
    side_share: float = 0.5

    # -- the lines (core.lines): pieces and groups (passes 1-3) --
    #: a stroke is cut where it turns more than this (degrees) within cut_reach d_eps each
    #: side: a corner drawn in one motion (pass 1). decisions: "the pen stage"
    cut_angle: float = 70.0
    #: see cut_angle: a corner drawn rounded (radius up to about 2 d_eps) is one too.
    #: decisions: "the pen stage"
    cut_reach: float = 2.0
    #: ... but not where the stroke goes on turning the same way over the next cut_reach,
    #: on each side with ink there, at least this share as fast per length: a small round
    #: shape (an eye, a curl) is not a corner (pass 1; the same test decides the corners
    #: of pass 10). decisions: "a small round shape is not cut at corners", "a short round
    #: stroke judged at its own size"
    round_share: float = 0.5
    #: ink coming back within follow_reach of a stroke's earlier ink, over this many
    #: follow_reach back along it, is the stroke drawn over itself: a new piece (pass 1).
    #: decisions: "Where each tuned number comes from"
    back: float = 4.0
    #: pieces and lines are sampled this many d_eps apart (every pass). decisions: "Where
    #: each tuned number comes from"
    sample: float = 0.25
    #: a sample follows the nearest alive curve within this many d_eps (passes 1-2).
    #: decisions: "the pen stage"
    follow_reach: float = 1.0
    #: ... running along it, |cos| at least this (the merge angle); every pass's test of
    #: "running along" (passes 1, 2, 5, 8). decisions: "the pen stage's join keeps each line
    #: whole"
    follow_cos: float = 0.866
    #: two pieces following the same alive curves are one line along this share of the
    #: shorter (pass 3). decisions: "the pen stage"
    shared_share: float = 0.5
    #: ... or this many d_eps long (pass 3). decisions: "the pen stage"
    shared_length: float = 2.0
    #: ... overlapping, or at most this many d_eps apart (pass 3). decisions: "the pen stage"
    shared_gap: float = 1.0
    #: a stroke of which this share lies within twin_reach d_eps of another stroke, as
    #: that share of the other lies within twin_reach of it, is a pass of the other's line,
    #: drawn again whole, and is not cut at its corners (pass 1). decisions: "a stroke drawn
    #: again whole is not cut at its corners"
    twin_share: float = 0.8
    #: ... (pass 1). decisions: "a stroke drawn again whole is not cut at its corners"
    twin_reach: float = 1.0

    # -- the lines: a group's fit and its checks (passes 4, 8) --
    #: a piece stays in its group where this share of it lies within member_reach of the
    #: group's line: whole lines against doubled ones. decisions: "a page of drawings gives
    #: each the width it gets alone"
    member_share: float = 0.5
    #: how far off the middle a loose pass lies (d_eps): ink within it is the line's (pass
    #: 4), beyond every line's a line of its own (pass 8); two passes lie within twice it
    #: of each other, or part (pass 4). decisions: "a piece the fitted line leaves from its
    #: middle draws another line"; "two passes that run along each other and then part"
    member_reach: float = 1.5
    #: a piece parting from the spine within this many member_reach of its end extends it.
    #: decisions: "Where each tuned number comes from"
    end_zone: float = 2.0
    #: a piece coming back round closes a spine into a loop only when it is longer than this
    #: many member_reach; a spine whose own ends meet, where they lie within member_reach
    #: and within 1/loop_length of its length of each other (a small ring drawn whole
    #: closes; a U does not). decisions: "Where each tuned number comes from"; "a band in
    #: open paper"
    loop_length: float = 4.0
    #: the centreline's bins along its spine (d_eps). decisions: "ink no line stands for
    #: becomes a line"
    bin: float = 0.25
    #: ... and the Gaussian smoothing the line moved to their medians (sigma, d_eps; at
    #: most a line's length / 4 pi). decisions: "one output stage, lines from the pen";
    #: "the centreline smoothed as a line"
    smooth: float = 0.5
    #: a band free of ink parts two lines where wider than fill_gap, or than this times the
    #: wider ink beside it (passes 4-6). decisions: "groups split where a band free of ink
    #: runs all along them"; "two bundles, not a band all along"
    band_ratio: float = 1.0
    #: ... and at least this many d_eps. decisions: "groups split where a band free of ink
    #: runs all along them"; "two bundles, not a band all along"
    band_floor: float = 0.5
    #: ... and it parts two bundles of two passes or more each where wider than this times
    #: the wider one's spread, whatever lies around them; else only where other ink lies
    #: near (apart, apart_share) (passes 4-6). decisions: "a band in open paper"
    tight_ratio: float = 2.0
    #: a piece with this many samples beside the line or more is judged by the band test
    #: (pass 4). decisions: "Where each tuned number comes from"
    band_samples: int = 4
    #: a line's ink spreads from it by this percentile of its distances (passes 5-6).
    #: decisions: "Where each tuned number comes from"
    spread_percentile: float = 90.0

    # -- the lines: joins and absorbs (passes 5, 6) --
    #: two lines are joined where this share of the shorter lies within d_eps of the
    #: longer, running along it (pass 5). decisions: "groups split where a band free of ink
    #: runs all along them"
    along_share: float = 0.6
    #: ... running within this |cos| of the longer's direction (15 degrees): fitted lines
    #: are smooth, so their direction is their course, not a pen's tremor (the raw
    #: pieces' follow_cos allows 30); a line meeting another at 20 degrees or more (an
    #: arrowhead's leg, a letter's stroke leaving a bowl) is another line (pass 5).
    #: decisions: "a line lies along another within 15 degrees"
    along_cos: float = 0.966
    #: rounds of pass 5 at most. decisions: "the pen stage's join run until a round joins
    #: nothing"
    join_rounds: int = 2
    #: a join or an absorb stands where the joint line keeps join_share of each line within
    #: this many d_eps. decisions: "a line's end stretch drawn along another line"
    join_reach: float = 0.5
    #: see join_reach: a line kept whole, as the scorer counts one. decisions: "the pen
    #: stage's join keeps each line whole"
    join_share: float = 0.8
    #: ... or where no other line lies within this many times the farthest move; and a
    #: band between two inks parts them only where other ink lies within this many times
    #: its width (passes 4-6) ... decisions: "a join or an absorb stands where the joint
    #: line keeps the lines in place"; "a band in open paper"
    apart: float = 3.0
    #: ... along this share of the joint line (of the two inks): one loose line in open
    #: paper. decisions: "a join or an absorb stands where the joint line keeps the lines
    #: in place"; "a band in open paper"
    apart_share: float = 0.5
    #: a line shorter than this many d_eps is a crumb or hook, absorbed where within
    #: absorb_reach of a longer line (pass 6), and no line of its own (passes 4, 8).
    #: decisions: "a piece the fitted line leaves from its middle"
    crumb: float = 3.0
    #: see crumb (d_eps). decisions: "a join or an absorb stands where the joint line keeps
    #: the lines in place"
    absorb_reach: float = 0.75

    # -- the lines: ink no line stands for (pass 8), junctions (pass 9) --
    #: stretches that parted from the lines are one where this share of the shorter lies
    #: within member_reach of the other. decisions: "ink no line stands for becomes a line"
    together_share: float = 0.5
    #: an end within this many d_eps of another line meets it (passes 7-9). decisions: "one
    #: output stage, lines from the pen"
    snap: float = 1.0
    #: ... and snap and overshoot (passes 7-9) count d_eps as at least this (D): how far a
    #: hand's end misses a line does not narrow with a dense drawing's width. decisions:
    #: "the width follows dense ink below the paper's"
    meet_alpha: float = PAPER_ALPHA
    #: an end crossing a line and running on at most this many d_eps is cut there.
    #: decisions: "one output stage, lines from the pen"
    overshoot: float = 2.0
    #: the met line's direction is taken over this share of snap each side of the foot.
    #: decisions: "Where each tuned number comes from"
    meet_tangent: float = 0.25
    #: a line no longer than this many overshoots is not trimmed. decisions: "Where each
    #: tuned number comes from"
    trim_length: float = 2.0
    #: an end that would turn by more than ``meet_turn`` to join a line's nearest point is
    #: bent onto it over this many times its gap (pass 9). decisions: "an end meets a line
    #: carried straight on, or bent gently"
    meet_bend: float = 4.0
    #: an end whose straight join to a line's nearest point would turn by more than this
    #: (degrees) is bent onto it instead; a smaller turn is a corner the join keeps (pass
    #: 9). decisions: "an end meets a line carried straight on, or bent gently"
    meet_turn: float = 90.0

    # -- fills (SimplifyResult.fill_regions) --
    #: regions under this share of the drawing's box are crumbs. decisions: "fills are the
    #: regions the clean lines close"
    fill_min_share: float = 1e-5
    #: lines stopping within twice this many d_eps of each other close a region.
    #: decisions: "fills are the regions the clean lines close"
    fill_close: float = 0.25
    #: a free end is carried on this many d_eps to the line it meets. decisions: "fills are
    #: the regions the clean lines close"
    fill_reach: float = 2.0


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
                  joint fit keeps both (:mod:`core.lines.join`, :mod:`core.lines.absorb`);
                  so may two with no other ink near them, whatever the band (one loose
                  line drawn in open paper: :func:`core.lines.fit.one_loose_line`).
                  "auto" (default): the ink's spacing (:func:`ink_spacing`), at most
                  ``tuning.fill_gap_share`` of d_eps; 0: never, whatever lies near. A
                  result's params hold the number used
    target_patches, target_curves   optional: also stop once this few remain
    max_curves    refuse a sketch whose strokes cross into more curves than this (None: no
                  limit): the largest real sketches make about 17,000, and one of 100,000
                  takes many minutes
    skip          names of pen passes to leave out, for ablations (:data:`core.lines.PASSES`)
    tuning        the pipeline's tuned numbers (:class:`Tuning`)
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

    def resolved(self, unit_strokes: list[np.ndarray] | None = None) -> ResolvedParams:
        """These params with alpha and fill_gap numbers, fractions of the drawing's diagonal
        (the unit frame's, :class:`core.io.cleaning.Normalisation`): the narrowest that
        :meth:`widths` tries, the one kept whatever its result.

        "auto" follows the ink when ``unit_strokes`` (the drawing's strokes in the unit
        frame, without ink far away) are given: ``tuning.spacing_share`` times their
        spacing (:func:`ink_spacing`), no narrower than ``tuning.narrowest_alpha`` and no
        wider than ``tuning.loose_alpha``. A sparse drawing, whose passes lie far apart for
        its size (cartoons, handwriting, test drawings), gets a wider bundle; a dense one
        (product sketches: many close construction lines) a narrower one than the paper's
        0.012, so that its close lines stay apart. (How each bound was measured:
        ``docs/decisions.md``, "The auto width's bounds" and "the width follows dense ink
        below the paper's".)

        Then never more than ``tuning.stroke_share`` of the median length of the strokes (nor
        less than :data:`MIN_ALPHA`): a bundle is never wider than half the strokes that
        make it are long. Where a drawing is many small parts spread wide, the width
        follows the parts, not the spread.

        "auto" fill_gap is the ink's spacing, at most ``tuning.fill_gap_share`` of d_eps
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
        >>> round(SimplifyParams().resolved(hatch).alpha, 4)  # dense: narrower, 1.5 x 0.4%
        0.0062
        >>> short = [np.array([[0.0, 0.0], [0.02, 0.0]])] * 3  # strokes 2% of the diagonal
        >>> round(SimplifyParams().resolved(short).alpha, 6)
        0.01
        """
        return self._widths(unit_strokes, wider=False)[-1]

    def widths(self, unit_strokes: list[np.ndarray] | None = None) -> list[ResolvedParams]:
        """The resolved params that :func:`core.simplify` tries, widest first: the last is
        :meth:`resolved`'s (at most ``tuning.loose_alpha``), kept whatever its result;
        before it, for a sparse drawing under "auto" alpha whose ink's width
        (``tuning.spacing_share`` times its spacing, at most ``tuning.widest_alpha`` and the
        median-length cap) is at least ``tuning.wide_from``, that width and the one halfway
        down to loose_alpha, each unless more than ``tuning.wide_banded`` of the ink lies in
        bands of lines a bundle that wide cannot hold (:func:`banded_shares`), and each kept
        only where its result keeps the ink (``tuning.keep_reach``).

        Why tried and checked: ``docs/decisions.md``, "Wider where the ink allows".

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
                ) -> list[ResolvedParams]:
        if self.alpha != "auto" and self.fill_gap != "auto":
            return [ResolvedParams.of(self)]
        t = self.tuning
        spacing = ink_spacing(unit_strokes, t.ink_cell) if unit_strokes else None
        alphas = [self.alpha]
        if self.alpha == "auto":
            alphas = [PAPER_ALPHA]
            if unit_strokes:
                cap = t.stroke_share * float(np.median(total_lengths(unit_strokes)))
                wide = min(t.spacing_share * spacing, t.widest_alpha, cap)
                alphas = [max(min(max(t.spacing_share * spacing, t.narrowest_alpha),
                                  t.loose_alpha, cap), MIN_ALPHA)]
                if wider and wide >= t.wide_from:
                    tries = [wide, (wide + t.loose_alpha) / 2]
                    alphas = [w for w, banded in zip(tries, banded_shares(unit_strokes, tries,
                                                                           t))
                              if banded <= t.wide_banded] + alphas
        return [ResolvedParams.of(replace(self, alpha=alpha,
                                          fill_gap=self._fill_gap(alpha, spacing)))
                for alpha in alphas]

    def _fill_gap(self, alpha: float, spacing: float | None) -> float:
        if self.fill_gap != "auto":
            return self.fill_gap
        fill_gap = self.tuning.fill_gap_share * alpha
        return fill_gap if spacing is None else min(spacing, fill_gap)

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class ResolvedParams(SimplifyParams):
    """:class:`SimplifyParams` resolved for one drawing: alpha and fill_gap are numbers
    (fractions of the drawing's diagonal), never "auto". Made once, by
    :meth:`SimplifyParams.resolved` or :meth:`SimplifyParams.widths` (or by :meth:`of`
    from params whose numbers are given, as a record's are); every stage after the width
    (the complex, the merge loop, the lines, a replay) takes this type, and resolves
    nothing again.

    >>> p = SimplifyParams().resolved()
    >>> type(p).__name__, p.alpha, p.resolved() is p
    ('ResolvedParams', 0.012, True)
    >>> ResolvedParams.of(SimplifyParams(alpha=0.02, fill_gap=0.01)).alpha
    0.02
    >>> ResolvedParams.of(SimplifyParams())
    Traceback (most recent call last):
    ...
    core.sketch.SketchError: params are not resolved: alpha 'auto', fill_gap 'auto'
    """

    #: the bundle width used, a fraction of the drawing's diagonal
    alpha: float = PAPER_ALPHA
    #: the widest band free of ink inside one bundle used, a fraction of the diagonal
    fill_gap: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.alpha == "auto" or self.fill_gap == "auto":
            raise SketchError(f"params are not resolved: alpha {self.alpha!r}, "
                              f"fill_gap {self.fill_gap!r}")

    @classmethod
    def of(cls, params: SimplifyParams) -> ResolvedParams:
        """``params`` as resolved params, where their alpha and fill_gap are numbers;
        raises :class:`SketchError` where either is "auto"."""
        if isinstance(params, cls):
            return params
        return cls(**{f.name: getattr(params, f.name) for f in fields(params)})

    def resolved(self, unit_strokes: list[np.ndarray] | None = None) -> ResolvedParams:
        return self

    def widths(self, unit_strokes: list[np.ndarray] | None = None) -> list[ResolvedParams]:
        return [self]


def ink_spacing(unit_strokes: list[np.ndarray], cell_size: float = Tuning.ink_cell
                ) -> float:
    """How far apart the ink lies, in the unit frame: the area the ink occupies (cells
    ``cell_size`` wide holding any of it) over its length. One line through empty space
    gives about the cell size; passes drawn side by side share cells and give less; many
    close lines (a product sketch's construction lines, hatching) give much less. It
    depends on the drawing alone, not on where it lies or how big it is (the unit frame),
    and it follows the sketch's best bundle width (by the dev sketches' labels, a
    correlation of 0.56 in logs; product sketches 0.0064, median of the others 0.0105).

    >>> t = np.linspace(0, 1, 101)[:, None]
    >>> round(ink_spacing([np.hstack([t, 0.5 + 0 * t])]), 3)  # a line: its cells' width
    0.02
    """
    points, _ = resample_each(unit_strokes, cell_size / 8)
    length = float(total_lengths(unit_strokes).sum())
    if length <= 0:
        return 0.0
    cell = np.floor(points / cell_size).astype(np.int64)
    cell -= cell.min(axis=0)
    cells = len(np.unique(cell[:, 0] * (int(cell[:, 1].max()) + 1) + cell[:, 1]))
    return cells * cell_size ** 2 / length


def banded_shares(unit_strokes: list[np.ndarray], widths: list[float],
                  tuning: Tuning = Tuning()) -> list[float]:
    """For each width: the share of the ink, in the unit frame, that a bundle that wide
    cannot hold. That is where the section square to a stroke (every quarter of the
    width, twice the width each side) meets passes running along it (|cos| at least
    ``tuning.band_cos``) chained by gaps of at most the width into a band wider than it, unless the
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
    return [_banded_share(unit_strokes, segments, width, tuning) for width in widths]


def _banded_share(unit_strokes: list[np.ndarray], segments: Segments, width: float,
                  tuning: Tuning) -> float:
    points, counts = resample_each(unit_strokes, width / 4)
    tangent = np.concatenate([tangents(p) for p in split(points, counts)])
    cross = segments.crossings(points, tangent, 2 * width, tuning.band_cos)
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
                     width, tuning.swap_share)] = False
    return float(banded.mean())


def _swapping(owner: np.ndarray, passing: np.ndarray, offset: np.ndarray,
              section: np.ndarray, width: float, share: float) -> np.ndarray:
    """The sections, among those given, where another stroke in the band lies more than
    half the width to one side of the section's stroke along at least ``share``
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
        share: see above (``Tuning.swap_share``).

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
    swaps = np.minimum(below, above) >= share * np.bincount(group)
    return section[other][swaps[group]]
