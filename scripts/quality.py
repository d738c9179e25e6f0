"""Quality of the output on every real sketch, two at a time: the measures of the clean-lines
issue, per source, with the five worst sketches of each, far-ink invariance, and a page of
copies of a sketch against the sketch alone.

    python scripts/quality.py OUT.json [--root TREE] [--only PATTERN] [--jobs N] [--svg DIR]
                              [--data DIR] [--lines STAGE] [--skip PASS,...]
                              [--tuning NAME=VALUE,...] [--param NAME=VALUE,...]
                              [--anchor]
    python scripts/quality.py --compare BEFORE.json AFTER.json [--pictures DIR --before-root
                              TREE]

Measures per sketch (``bench_simplify.measure``; the scorer is ``scripts/metrics.py``, which
shares no code with ``core``): doubled, ink kept within 2% of the diagonal, coverage at 1%,
fidelity in px, output strokes per input stroke and per intended curve, and on the lift3d
sketches the F-score at 1% and the tight recall at 0.4% of the diagonal; and of the input,
too_wide: the share of its ink that no single line keeps within 2% of the diagonal (its
intended curve drawn wider than 4% across). A sketch doubled more than ``WIDE_SHARE`` is
listed with it: where too_wide is above that share too, ink kept and no doubled line cannot
both hold, and no width of bundle settles it. ``--root``
simplifies with another checkout's ``core`` (a ``git worktree`` of the commit before), so
that before and after are scored by the same scorer. ``--svg`` writes each output there.
``--skip`` leaves pen passes out and ``--tuning`` changes the pen's tuned constants
(``core.params.Tuning``), for ablations scored by the same scorer; ``--param`` changes a
numeric option of ``core.SimplifyParams`` (smoothing, fit_error, ...) the same way.
``--data`` scores
another folder of .scap sketches laid out as ``../shared/data`` (a source folder each, a
lift3d reference ``full_fit.scap`` beside its sketch), for example sketches held
out from tuning; the folder is recorded in OUT.json for ``--pictures``. ``--anchor``
scores one line fitted per labelled cluster instead (``metrics.cluster_reference``): what
a grouping as good as the labels gives with nothing smarter than medians, the ceiling to
measure the grouping against.

``--pictures`` with ``--compare`` draws the five worst sketches of AFTER by doubled, ink
kept, strokes per stroke in and tight recall, each as rough input | before (the checkout
``--before-root``) | after (``--root``), into DIR.

Far-ink invariance: a few sketches simplified alone and with one short stroke ten diagonals
away; the share of the drawing's output that moved more than 0.5% of the diagonal. A page:
the same sketches tiled 3 x 3 a fifth of their size apart, each copy against the sketch
alone, with the run's options.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE.parent.parent / "shared" / "data"
MEASURES = ("whole_lines", "whole_lines_twins", "whole_lines_input", "doubled_ref",
            "doubled_ref_clear", "doubled_ref_floor",
            "chamfer_px", "doubled",
            "ink_kept", "coverage", "fidelity_px", "per_in", "per_intended", "f_score",
            "tight_recall", "too_wide", "group_precision", "group_recall", "wobble", "hooks",
            "close_parallels")
#: for each measure, whether higher is better (the worst are the other end)
HIGHER_IS_BETTER = {"whole_lines": True, "whole_lines_twins": True,
                    "whole_lines_input": True, "doubled_ref": False,
                    "doubled_ref_clear": False, "doubled_ref_floor": False,
                    "chamfer_px": False, "doubled": False, "ink_kept": True, "coverage": True,
                    "fidelity_px": False,
                    "per_in": False, "per_intended": False, "f_score": True,
                    "tight_recall": True, "too_wide": False, "group_precision": True,
                    "group_recall": True, "wobble": False, "hooks": False,
                    "close_parallels": True}
#: the doubled share beyond which a sketch is listed, with its too_wide (the issue's worst)
WIDE_SHARE = 0.25
#: the measures whose worst sketches are listed and drawn
WORST_OF = ("whole_lines", "doubled_ref", "chamfer_px", "doubled", "ink_kept", "per_in",
            "group_recall", "group_precision", "wobble")
FAR_INK = ("strokeaggregator_labels/for_second_round/house_label_101.scap",
           "strokestrip_inputs/examples/study_inputs/Bee04_SA_cluster.scap",
           "lift3d_opensketch/CurvedStrokesPython/full_clusters/designer2/trash_bin/view1/"
           "lines_separation/full_cluster.scap")

__all__ = ["assignments", "main", "scored", "short_name", "summary", "use_checkout", "worst"]


def use_checkout(root: str) -> None:
    """Import ``core`` from ``root`` before the scripts, which put this checkout first."""
    sys.path[:0] = [root, str(HERE)]
    import core  # noqa: F401 - the scripts' own path entry would win once they are imported

    assert Path(core.__file__).resolve().parent.parent == Path(root).resolve(), core.__file__


def input_groups(sketch, result) -> list[int] | None:
    """The output stroke that draws each of ``sketch``'s strokes (``result.groups``), -1
    for a stroke cleaning dropped, matched by ``source_id``; None for a checkout whose
    result has no groups (before 2026-12-04)."""
    groups = getattr(result, "groups", None)
    if groups is None:
        return None
    of = {s.source_id: g for s, g in zip(result.cleaned.strokes, groups.tolist())}
    return [of.get(s.source_id, -1) for s in sketch.strokes]


def assignments(text: str) -> dict[str, float]:
    """``name=value,...`` (``--tuning``, ``--param``) as a dict; empty text, none. A whole
    number is an int (``samples``, ``join_rounds`` must be), any other a float.

    >>> assignments("smoothing=1,fit_error=0.25")
    {'smoothing': 1, 'fit_error': 0.25}
    >>> assignments("")
    {}
    """
    return {k: int(v) if v.strip().lstrip("+-").isdigit() else float(v)
            for k, v in (item.split("=") for item in text.split(",") if item)}


def score_one(args: tuple[str, str, str, str | None, dict]) -> tuple[str, dict]:
    root, data, path, svg_dir, options = args
    use_checkout(root)
    from bench_simplify import measure

    from core import SimplifyParams, read_sketch, simplify, write_sketch

    sketch = read_sketch(path)
    if options.get("anchor"):  # one line fitted per labelled cluster: where the ceiling is
        from bench_simplify import diagonal
        from metrics import cluster_reference

        clusters = [s.cluster for s in sketch.strokes]
        out = cluster_reference([s.points for s in sketch.strokes], clusters,
                                diagonal(sketch))
        return path, measure(Path(path), sketch, out, clusters)
    try:
        result = simplify(sketch, SimplifyParams(**options))
    except Exception as exc:  # noqa: BLE001 - a failure is a result here
        return path, {"error": f"{type(exc).__name__}: {exc}"}
    if svg_dir:
        name = Path(path).relative_to(data).as_posix().replace("/", "__")
        write_sketch(result.to_sketch(), Path(svg_dir) / (Path(name).stem + ".svg"))
    return path, measure(Path(path), sketch, [s.points for s in result.strokes],
                         input_groups(sketch, result))


def far_ink(args: tuple[str, str]) -> tuple[str, float]:
    """The share of a drawing's output moved by one stroke ten diagonals away."""
    root, path = args
    use_checkout(root)
    from bench_simplify import diagonal
    from metrics import changed

    from core import SimplifyParams, Sketch, Stroke, read_sketch, simplify

    sketch = read_sketch(path)
    diag = diagonal(sketch)
    pts = np.concatenate([s.points for s in sketch.strokes])
    far = pts.max(axis=0) + 10 * diag + np.array([[0.0, 0.0], [0.02 * diag, 0.01 * diag]])
    alone = simplify(sketch, SimplifyParams()).strokes
    both = simplify(Sketch(list(sketch.strokes) + [Stroke(far)]), SimplifyParams()).strokes
    near = [s.points for s in both if s.points.min(axis=0)[0] < pts.max(axis=0)[0] + diag]
    return path, changed([s.points for s in alone], near, 0.005 * diag, 0.0025 * diag)


#: copies of a sketch on one page, in rows and columns, a fifth of its size apart
PAGE_COPIES = 3


def page(args: tuple[str, str, dict]) -> tuple[str, dict]:
    """A page of :data:`PAGE_COPIES` x PAGE_COPIES copies of a sketch, each copy's output
    against the sketch's alone (the clean-lines issue: a page of many drawings gives each
    the lines it gets alone): the share moved more than 0.5% of the diagonal (median and
    worst over the copies) and the copy's ink within 1% of it (worst)."""
    root, path, options = args
    use_checkout(root)
    from bench_simplify import diagonal
    from metrics import changed, coverage

    from core import SimplifyParams, Sketch, Stroke, read_sketch, simplify

    sketch = read_sketch(path)
    diag = diagonal(sketch)
    ink = [s.points for s in sketch.strokes]
    points = np.concatenate(ink)
    lo, hi = points.min(axis=0), points.max(axis=0)
    step = (hi - lo) * 1.2
    n = PAGE_COPIES
    alone = [s.points for s in simplify(sketch, SimplifyParams(**options)).strokes]
    sheet = simplify(Sketch([Stroke(p + step * [i, j]) for i in range(n) for j in range(n)
                             for p in ink]), SimplifyParams(**options)).strokes
    moved, kept = [], []
    for i in range(n):
        for j in range(n):
            offset = step * [i, j]
            mine = [s.points - offset for s in sheet
                    if np.all(np.abs(s.points.mean(axis=0) - offset - (lo + hi) / 2)
                              <= 0.6 * step)]
            moved.append(changed(alone, mine, 0.005 * diag, 0.0025 * diag))
            kept.append(coverage(ink, mine, 0.01 * diag))
    return path, {"moved": float(np.median(moved)), "moved_worst": float(max(moved)),
                  "ink_kept_1pct": float(min(kept))}


def output_of(args: tuple[str, str, dict]) -> list[np.ndarray]:
    """The output polylines of one sketch, simplified by the checkout at ``root`` with the
    run's options (its ``SimplifyParams`` fields)."""
    root, path, options = args
    use_checkout(root)
    from core import SimplifyParams, read_sketch, simplify

    return [s.points for s in simplify(read_sketch(path), SimplifyParams(**options)).strokes]


def worst_pictures(after: dict, roots: tuple[str, str], out_dir: Path, jobs: int) -> None:
    """Input | before | after of the five worst sketches by each of ``WORST_OF`` (of
    ``after``, simplified with its run's options), one PNG each (drawn by the report's
    :func:`picture`), the outputs over the reference in grey (lift3d's, else one line
    fitted per labelled cluster)."""
    from bench_simplify import diagonal, intended_curves
    from metrics import cluster_reference
    from report import picture

    from core import read_sketch

    data = Path(after.get("_data", DATA))
    ok = scored(after)
    chosen: dict[str, str] = {}
    for m in WORST_OF:
        for k in worst(ok, m):
            chosen.setdefault(k, m)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [str(data / k) for k in chosen]
    outs = {}
    for root in roots:  # a pool each: a worker imports one checkout's core
        with ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
            outs[root] = list(pool.map(output_of, [(root, p, after.get("_options", {}))
                                                   for p in paths]))
    for k, (key, measure) in enumerate(chosen.items()):
        sketch = read_sketch(data / key)
        ink = [s.points for s in sketch.strokes]
        reference = intended_curves(data / key, sketch)[1]
        if reference is None:
            reference = cluster_reference(ink, [s.cluster for s in sketch.strokes],
                                          diagonal(sketch))
        panels = [(f"{short_name(key)}, worst by {measure} ({ok[key][measure]:.3f} after): "
                   f"input, {len(ink)} strokes", ink)] + [
            (f"{label}: {len(outs[root][k])} strokes", outs[root][k])
            for label, root in zip(("before", "after"), roots)]
        picture(out_dir / f"{measure}_{short_name(key).replace('/', '_')}.png", panels,
                under=reference)


def short_name(key: str) -> str:
    """A sketch's path under the data folder, shortened: designer/object for lift3d."""
    parts = Path(key).parts
    if parts[-1] == "full_cluster.scap":
        return f"{parts[-5]}/{parts[-4]}"
    return Path(key).stem


def scored(rows: dict[str, dict]) -> dict[str, dict]:
    """The sketches of a run that were scored (not the far-ink rows, not the failures)."""
    return {k: v for k, v in rows.items() if not k.startswith("_") and "error" not in v}


def worst(ok: dict[str, dict], measure: str, n: int = 5) -> list[str]:
    """The ``n`` worst of the scored sketches ``ok`` by ``measure`` (ties by name)."""
    have = sorted(((v[measure], k) for k, v in ok.items()
                   if measure in v and not np.isnan(v[measure])),
                  reverse=not HIGHER_IS_BETTER[measure])
    return [k for _, k in have[:n]]


def summary(rows: dict[str, dict]) -> str:
    """Medians per source and overall, and the five worst sketches of each measure."""
    lines = []
    ok = scored(rows)
    sources = sorted({k.split("/")[0] for k in ok})
    for source in [*sources, "all"]:
        mine = [v for k, v in ok.items() if source == "all" or k.startswith(source + "/")]
        parts = []
        for m in MEASURES:
            vals = [v[m] for v in mine if m in v]
            if vals:
                parts.append(f"{m} {np.nanmedian(vals):.3f}")
        lines.append(f"{source} ({len(mine)}): " + ", ".join(parts))
    for m in WORST_OF:
        lines.append(f"worst {m}: " + "; ".join(f"{short_name(k)} {ok[k][m]:.3f}"
                                                  for k in worst(ok, m)))
    left_doubled = sorted((k for k, v in ok.items() if v["doubled"] > WIDE_SHARE),
                          key=lambda k: -ok[k]["doubled"])
    wide = [k for k in left_doubled if ok[k].get("too_wide", 0.0) > WIDE_SHARE]
    lines.append(f"doubled more than {WIDE_SHARE}: {len(left_doubled)}, of which {len(wide)} "
                 "with too_wide above it too (doubled/too_wide): " + "; ".join(
                     f"{short_name(k)} {ok[k]['doubled']:.3f}/{ok[k].get('too_wide', np.nan):.3f}"
                     for k in left_doubled))
    below = [k for k, v in ok.items()
             if v.get("whole_lines", 1.0) < v.get("whole_lines_input", 0.0) - 1e-9]
    lines.append(f"whole lines below the rough input's own: {len(below)} of {len(ok)}")
    more = [k for k, v in ok.items() if v["strokes_out"] > v["strokes_in"]]
    lines.append(f"sketches with more strokes out than in: {len(more)}")
    failed = [k for k, v in rows.items() if not k.startswith("_") and "error" in v]
    lines.append(f"failures: {len(failed)} {failed[:3]}")
    if "far_ink" in rows.get("_far", {}):
        lines.append("far ink moved: " + ", ".join(f"{short_name(k)} {x:.3f}"
                                                   for k, x in rows["_far"]["far_ink"].items()))
    if "page" in rows.get("_far", {}):
        lines.append(f"a page of {PAGE_COPIES} x {PAGE_COPIES} copies, each against the sketch "
                     "alone (moved median/worst, ink within 1% worst): " + ", ".join(
                         f"{short_name(k)} {x['moved']:.3f}/{x['moved_worst']:.3f}, "
                         f"{x['ink_kept_1pct']:.3f}" for k, x in rows["_far"]["page"].items()))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?")
    ap.add_argument("--root", default=str(HERE.parent), help="checkout to import core from")
    ap.add_argument("--only", default="", help="substring of the sketch paths to run")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--svg", help="write each output SVG into this folder")
    ap.add_argument("--data", type=Path, default=DATA,
                    help="folder of sketches to score, laid out as ../shared/data")
    ap.add_argument("--lines", help="the output stage of a --root from before the line "
                    "stage became the only one (8618027: 'pen' or 'complex'); default the "
                    "checkout's own")
    ap.add_argument("--skip", default="", help="pen passes to leave out, comma-separated "
                    "(an ablation)")
    ap.add_argument("--tuning", default="", help="pen tuning to change, as name=value,... "
                    "(core.params.Tuning)")
    ap.add_argument("--param", default="", help="options to change, as name=value,... "
                    "(core.SimplifyParams' numeric fields: smoothing, fit_error, ...)")
    ap.add_argument("--anchor", action="store_true", help="score one line fitted per "
                    "labelled cluster instead of a simplification: the ceiling a grouping "
                    "as good as the labels gives with a plain median fit")
    ap.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"))
    ap.add_argument("--pictures", type=Path, help="with --compare: draw the worst here")
    ap.add_argument("--before-root", help="with --pictures: the checkout of BEFORE")
    args = ap.parse_args(argv)
    if args.compare:
        before, after = (json.loads(Path(p).read_text()) for p in args.compare)
        print("BEFORE\n" + summary(before) + "\n\nAFTER\n" + summary(after))
        if args.pictures and args.before_root:
            roots = (str(Path(args.before_root).resolve()), str(Path(args.root).resolve()))
            worst_pictures(after, roots, args.pictures, args.jobs)
        return 0
    data = args.data.resolve()
    if not data.is_dir():
        print(f"no sketches at {data}: nothing to score")
        return 0
    files = sorted(str(p) for p in data.rglob("*.scap")
                   if p.name != "full_fit.scap" and args.only in str(p))
    if args.svg:
        Path(args.svg).mkdir(parents=True, exist_ok=True)
    root = str(Path(args.root).resolve())
    with ProcessPoolExecutor(args.jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        options = {"lines": args.lines} if args.lines else {}
        if args.skip:
            options["skip"] = tuple(args.skip.split(","))
        if args.tuning:
            options["tuning"] = assignments(args.tuning)
        options |= assignments(args.param)
        if args.anchor:
            options = {"anchor": True}
        rows = dict(pool.map(score_one, [(root, str(data), f, args.svg, options)
                                         for f in files]))
        far = [str(data / p) for p in FAR_INK if (data / p).exists() and args.only in p
               and not args.anchor]
        far_rows = dict(pool.map(far_ink, [(root, f) for f in far]))
        page_rows = dict(pool.map(page, [(root, f, options) for f in far]))
    out = {str(Path(k).relative_to(data)): v for k, v in rows.items()}
    out["_far"] = {"far_ink": {str(Path(k).relative_to(data)): v for k, v in far_rows.items()},
                   "page": {str(Path(k).relative_to(data)): v for k, v in page_rows.items()}}
    out["_data"] = str(data)
    out["_options"] = options  # what --pictures simplifies with
    if args.out:
        Path(args.out).write_text(json.dumps(out, indent=1))
    print(summary(out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
