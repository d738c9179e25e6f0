"""Rough passes drawn over known clean curves, scored against those curves: where the truth
is known exactly, a loss is the simplification's, not the reference's.

    python scripts/synthetic_passes.py OUT.json [--root TREE] [--jobs N] [--data DIR]
                                       [--param NAME=VALUE,...] [--tuning NAME=VALUE,...]
                                       [--kind KIND]

The clean curves (``--kind``) are the lift3d designers' ``full_fit.scap`` curves of
``../shared/data`` (``product``, read in place, never copied), or drawings made here from
the Hershey single-stroke fonts (the ``Hershey-Fonts`` package, MIT; a dev dependency):
``handwriting``, two lines of cursive words (the ``scripts`` font, its coarse polylines
rounded by Chaikin's corner cutting), and ``icons``, four marker shapes side by side
(circles, boxes, triangles, stars, arrows: the ``markers`` font, corners kept), close
enough to be one drawing (not a page of drawings, each at its own size), and ``kanji``,
two glyphs of five strokes or more side by side (the ``japanese`` font, corners kept:
short ticks and dots beside long strokes; a wide stroke, which the font draws as two
lines, as one). Each curve is
drawn again as 2 to 4 passes: each pass offset from it by a constant (sigma 0.4% of the
diagonal D), a slow wander (0.3% D, wavelength 10-30% D) and a tremor (0.05% D), its ends
trimmed by up to 2% D or run on by up to 2% D along the curve's tangent; the seed is the
file's path (or the drawing's kind and number), so a run is repeatable.
The measures (``scripts/metrics.py``): whole lines of the output, of the passes
themselves and of one median fit per curve's passes (``cluster_reference`` given the true
labels: where the ceiling is); the grouping's pair precision and recall against the true
labels (a loss there is the grouping's, a loss beside a whole grouping the fit's); wobble
and doubled on the reference; medians, and the count of sketches whose output keeps fewer
curves whole than its own rough passes.

Unlike ``cluster_reference`` (the stand-in reference of the labelled sketches, itself a
median fit along the longest stroke, which keeps that stroke's wander), the reference here
is the curve the passes were drawn from.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import zlib
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import shapely
from quality import assignments, input_groups, use_checkout

HERE = Path(__file__).resolve().parent
DATA = HERE.parent.parent / "shared" / "data"
#: sigma of a pass's constant offset, amplitude of its wander, sigma of its tremor (D)
OFFSET, WANDER, TREMOR = 0.004, 0.003, 0.0005
#: the wander's wavelength range, and how far an end is trimmed or run on, at most (D)
WAVELENGTH, END = (0.1, 0.3), 0.02
#: a pass is sampled this often (D)
STEP = 0.002


def rough_passes(curves: list[np.ndarray], diagonal: float, seed: int,
                 offset: float = OFFSET) -> tuple[list[np.ndarray], list[int]]:
    """Each of ``curves`` drawn as 2 to 4 rough passes (see the module): the passes, and
    for each the index of the curve it was drawn from (its true label). ``offset`` is the
    sigma of a pass's constant offset (D).

    >>> line = np.array([[0.0, 0.0], [100.0, 0.0]])
    >>> passes, labels = rough_passes([line, line + 50], 500.0, 1)
    >>> all(np.abs(p[:, 1] - 50 * k).max() < 0.03 * 500 for p, k in zip(passes, labels))
    True
    >>> sorted(set(labels)), all(2 <= labels.count(k) <= 4 for k in (0, 1))
    ([0, 1], True)
    """
    rng = np.random.default_rng(seed)
    out, labels = [], []
    for label, curve in enumerate(curves):
        line = shapely.LineString(curve)
        if line.length <= 0:
            continue
        s = np.linspace(0, line.length, max(4, int(line.length / (STEP * diagonal))))
        points = shapely.get_coordinates(shapely.line_interpolate_point(line, s))
        tangent = np.gradient(points, axis=0)
        tangent /= np.maximum(np.hypot(*tangent.T), 1e-12)[:, None]
        normal = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)
        for _ in range(int(rng.integers(2, 5))):
            head = rng.uniform(-END, END / 2) * diagonal
            tail = rng.uniform(-END / 2, END) * diagonal
            wavelength = rng.uniform(*WAVELENGTH) * diagonal
            across = (rng.normal(0, offset * diagonal)
                      + WANDER * diagonal * np.sin(2 * np.pi * s / wavelength
                                                   + rng.uniform(0, 2 * np.pi))
                      + rng.normal(0, TREMOR * diagonal, len(s)))
            keep = (s >= max(0.0, -head)) & (s <= line.length + min(0.0, tail))
            if keep.sum() < 2:
                continue
            drawn = (points + normal * across[:, None])[keep]
            first, last = tangent[keep][0], tangent[keep][-1]
            if head > 0:
                drawn = np.vstack([drawn[0] - first * head, drawn])
            if tail > 0:
                drawn = np.vstack([drawn, drawn[-1] + last * tail])
            out.append(drawn)
            labels.append(label)
    return out, labels


#: the words the handwriting is written with, and how many drawings each Hershey kind has
WORDS = ["hello", "dog", "bumps", "quiet", "lovely", "sketch", "drawing", "flower", "bubble",
         "cycle", "kitten", "gallop", "whisper", "needle", "apple", "jolly", "boulevard",
         "office", "muddle", "zigzag"]
DRAWINGS = 20
#: the margin round a Hershey drawing, and the spacing of icons, in font units (a glyph
#: is about 20 tall, a marker 14 across)
MARGIN, SPACING = 6.0, 20.0
#: a kanji drawing: two glyphs of the ``japanese`` font side by side, this far apart (a
#: glyph is about 20 across), each of at least this many strokes (kanji, not kana)
KANJI_SPACING, KANJI_STROKES = 26.0, 5
#: a kanji stroke within this (font units) of a longer one along this share of it is the
#: font's second line of a wide stroke (:func:`single_lines`)
DOUBLE_REACH, DOUBLE_SHARE = 1.5, 0.8


def chaikin(points: np.ndarray, rounds: int = 2) -> np.ndarray:
    """Chaikin's corner cutting, ends kept: a coarse polyline rounded into a smooth curve.

    >>> chaikin(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]), 1).tolist()
    [[0.0, 0.0], [0.75, 0.0], [1.0, 0.25], [1.0, 1.0]]
    """
    for _ in range(rounds):
        if len(points) < 3:
            return points
        q = 0.75 * points[:-1] + 0.25 * points[1:]
        r = 0.25 * points[:-1] + 0.75 * points[1:]
        cut = np.stack([q, r], axis=1).reshape(-1, 2)[1:-1]
        points = np.vstack([points[:1], cut, points[-1:]])
    return points


def single_lines(curves: list[np.ndarray], reach: float = DOUBLE_REACH,
                 share: float = DOUBLE_SHARE) -> list[np.ndarray]:
    """``curves`` without the second line of a doubled stroke: a curve of which ``share``
    lies within ``reach`` (font units) of a longer one is left out. The ``japanese``
    font draws a wide stroke as two lines a unit apart (a hand draws it once) and a long
    one as overlapping pieces.

    >>> bar = np.array([[0.0, 0.0], [10.0, 0.0]])
    >>> [len(c) for c in single_lines([bar, bar[::-1] + [0.0, 0.8], bar + [0.0, 5.0]])]
    [2, 2]
    """
    lines = [shapely.LineString(c) for c in curves]
    order = sorted(range(len(curves)), key=lambda k: -lines[k].length)
    kept: list[int] = []
    for k in order:
        points = shapely.points(shapely.segmentize(lines[k], reach / 4).coords)
        if not any(float((shapely.distance(points, lines[o]) <= reach).mean()) >= share
                   for o in kept):
            kept.append(k)
    return [curves[k] for k in sorted(kept)]


def hershey_drawing(kind: str, index: int) -> tuple[list[np.ndarray], float, float]:
    """The clean curves of drawing ``index`` of a Hershey ``kind`` (see the module), laid
    on a canvas with a margin: the curves, the canvas's width and height."""
    from HersheyFonts import HersheyFonts

    rng = np.random.default_rng(zlib.crc32(f"{kind}/{index}".encode()))
    font = HersheyFonts()
    curves = []
    if kind == "handwriting":
        font.load_default_font("scripts")
        for row in range(2):
            words = " ".join(rng.choice(WORDS, 2, replace=False))
            curves += [chaikin(np.asarray(s, float)) + [0.0, 32.0 * row]
                       for s in font.strokes_for_text(words)]
    elif kind == "kanji":
        font.load_default_font("japanese")
        glyphs = [font.all_glyphs[c] for c in font.all_glyphs if c != " "
                  and len(font.all_glyphs[c].strokes) >= KANJI_STROKES]
        for cell in range(2):
            glyph = glyphs[int(rng.integers(len(glyphs)))]
            curves += single_lines([np.asarray(s, float) + [KANJI_SPACING * cell, 0.0]
                                    for s in glyph.strokes if len(s) >= 2])
    elif kind == "icons":
        font.load_default_font("markers")
        shapes = [c for c in font.all_glyphs if font.all_glyphs[c].strokes and c != " "]
        for cell in range(4):
            glyph = font.all_glyphs[shapes[int(rng.integers(len(shapes)))]]
            at = np.array([SPACING * (cell % 2), SPACING * (cell // 2)])
            curves += [np.asarray(s, float) + at for s in glyph.strokes]
    else:
        raise ValueError(f"no Hershey drawings of kind {kind!r}")
    curves = [c for c in curves if len(c) >= 2 and np.ptp(c, axis=0).max() > 0]
    corner = np.vstack(curves).min(axis=0) - MARGIN
    curves = [c - corner for c in curves]
    size = np.vstack(curves).max(axis=0) + MARGIN
    return curves, float(size[0]), float(size[1])


def clean_curves(source: str) -> tuple[list[np.ndarray], float, float]:
    """The clean curves of ``source`` (a ``full_fit.scap`` path, or ``KIND/INDEX`` of a
    Hershey kind) and its canvas's width and height."""
    kind, _, index = source.partition("/")
    if kind in ("handwriting", "icons", "kanji") and index.isdigit():
        return hershey_drawing(kind, int(index))
    from core import read_sketch

    clean = read_sketch(source)
    return [s.points for s in clean.strokes if len(s.points) >= 2], clean.width, clean.height


def synthetic_sketch(source: str, offset: float = OFFSET):
    """The rough passes of ``source``'s clean curves (:func:`clean_curves`,
    :func:`rough_passes`, seeded by the source's name) as a sketch, each stroke's
    ``source_id`` its index; with each pass's label, the clean curves and the diagonal."""
    from core import Sketch, Stroke

    reference, width, height = clean_curves(source)
    diagonal = float(np.hypot(width, height))
    ink, labels = rough_passes(reference, diagonal,
                               zlib.crc32(Path(source).as_posix().encode()), offset)
    sketch = Sketch([Stroke(p, source_id=k) for k, p in enumerate(ink)], width, height)
    return sketch, labels, reference, diagonal


def score_one(args: tuple[str, str, dict, float]) -> tuple[str, dict]:
    root, path, options, offset = args
    use_checkout(root)
    import metrics

    from core import SimplifyParams, simplify

    sketch, labels, reference, diagonal = synthetic_sketch(path, offset)
    ink = [s.points for s in sketch.strokes]
    result = simplify(sketch, SimplifyParams(**options))
    out = [s.points for s in result.strokes]
    precision, recall = metrics.pair_precision_recall(np.array(input_groups(sketch, result)),
                                                      np.array(labels))
    anchor = metrics.cluster_reference(ink, labels, diagonal)
    return path, {"whole_lines": metrics.whole_lines(out, reference, diagonal),
                  "whole_lines_input": metrics.whole_lines(ink, reference, diagonal),
                  "whole_lines_anchor": metrics.whole_lines(anchor, reference, diagonal),
                  "pair_precision": precision, "pair_recall": recall,
                  "wobble": metrics.wobble(out, reference, diagonal),
                  "doubled_ref": metrics.doubled_on_reference(out, reference, diagonal),
                  "strokes_in": len(ink), "strokes_out": len(out), "curves": len(reference)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?")
    ap.add_argument("--root", default=str(HERE.parent), help="checkout to import core from")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--data", type=Path, default=DATA, help="laid out as ../shared/data")
    ap.add_argument("--param", default="", help="options to change, as name=value,...")
    ap.add_argument("--tuning", default="", help="pen tuning to change, as name=value,...")
    ap.add_argument("--offset", type=float, default=OFFSET,
                    help="sigma of a pass's constant offset (fraction of D)")
    ap.add_argument("--kind", choices=("product", "handwriting", "icons", "kanji"),
                    default="product",
                    help="where the clean curves come from (see the module)")
    args = ap.parse_args(argv)
    if args.kind != "product":
        files = [f"{args.kind}/{k}" for k in range(DRAWINGS)]
    else:
        files = sorted(str(p) for p in args.data.resolve().rglob("full_fit.scap"))
    if not files:
        print(f"no lift3d references under {args.data}: nothing to score")
        return 0
    options = assignments(args.param)
    if args.tuning:
        options["tuning"] = assignments(args.tuning)
    root = str(Path(args.root).resolve())
    with ProcessPoolExecutor(args.jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        rows = dict(pool.map(score_one, [(root, f, options, args.offset) for f in files]))
    for name in ("whole_lines", "whole_lines_input", "whole_lines_anchor", "pair_precision",
                 "pair_recall", "wobble", "doubled_ref"):
        print(f"{name} {np.median([r[name] for r in rows.values()]):.3f}")
    below = sum(r["whole_lines"] < r["whole_lines_input"] for r in rows.values())
    print(f"whole lines below the rough passes' own: {below} of {len(rows)}")
    if args.out:
        Path(args.out).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
