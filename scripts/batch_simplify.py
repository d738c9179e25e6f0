"""Simplify the Grease Pencil drawings of .blend files, headless.

    blender -b SHOT.blend --python scripts/batch_simplify.py -- [options]
    python scripts/batch_simplify.py SHOT.blend [MORE.blend ...] [options]   (bpy wheel)

Options: --objects NAME[,NAME] (default every Grease Pencil object), --layers visible|active,
--frames all|current|A-B, --epsilon E (and --alpha, --samples), --output PATH (a file for
one input, a folder for several; default <name>_simplified.blend beside each input),
--in-place (overwrite the input after copying it to <name>.blend1), --jobs N, --summary
S.json, --fill-regions (the closed regions as fills too, on a layer under the lines),
--no-stable (each keyframe simplified on its own, not held to the one before),
--scheduler tcp://HOST:PORT (simplify on a Dask cluster: every file's drawings are read and
sent first, so that all files are in flight at once, then each file is opened again and
written as its results come; the workers need the project's Python package, not Blender),
--resume (skip the inputs whose output file exists; Blender saves whole files).
The result of each layer goes to a new layer above it, as the operator does. With more
than one job, one pool of worker processes, started before the first file is read, serves
every file.

Every file is reported: one that cannot be done (missing, not a readable .blend, empty,
without Grease Pencil, or failing while simplified) is named with its reason, and the rest
are done. Exit status: 0 when every file was done, 1 when any failed (the summary's
"failed" lists them), 2 with one line, before any work, on a bad option, an output folder
or summary path that cannot be written.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import shutil
import sys
import tempfile
import time
import traceback
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from types import SimpleNamespace

ROOT = Path(__file__).resolve().parents[1]
if "BLENDER_USER_RESOURCES" not in os.environ:  # keep the user's Blender config untouched
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="sketchsimp-batch-")

import bpy  # noqa: E402


class UsageError(Exception):
    """A problem with the command's input: one line, exit status 2, nothing done."""


class FileError(Exception):
    """One input file that cannot be done: named with the reason, the others still done."""


def script_argv(argv: list[str]) -> list[str]:
    if "--" in argv:  # blender -b --python x.py -- ARGS, or python x.py -- ARGS
        return argv[argv.index("--") + 1:]
    if bpy.app.binary_path == "":  # the bpy wheel: argv is [script, ARGS...]
        return argv[1:]
    return []  # inside Blender without '--': the rest was Blender's


def parse_frames(text: str) -> tuple[str, tuple[int, int] | None]:
    if text in ("all", "current"):
        return text, None
    try:
        first, last = (int(x) for x in text.split("-", 1))
    except ValueError:
        raise UsageError(f"bad frame range {text!r}: use all, current or FIRST-LAST") from None
    if first > last:
        raise UsageError(f"bad frame range {text!r}: {first} comes after {last}")
    return "range", (first, last)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="batch_simplify.py", description=__doc__.splitlines()[0])
    p.add_argument("blend", nargs="*", type=Path, help=".blend files or folders of them "
                   "(under blender -b: the open file when none is given)")
    p.add_argument("--objects", default="", help="comma-separated object names")
    p.add_argument("--layers", choices=("visible", "active"), default="visible")
    p.add_argument("--frames", default="all", help="all, current, or a range like 10-120")
    # no defaults written here: what is not given is SimplifyParams()'s own default
    p.add_argument("--epsilon", type=float, help="how far to simplify (default: the core's)")
    p.add_argument("--alpha", type=float, help="bundle width as a fraction of the diagonal")
    p.add_argument("--samples", type=int, help="Fourier descriptor samples N")
    p.add_argument("--stable", action=argparse.BooleanOptionalAction, default=True,
                   help="hold each keyframe's lines to the one before where the drawing did "
                   "not change (default: on)")
    p.add_argument("--fill-regions", action="store_true",
                   help="also write the closed regions as fills, on a layer under the lines")
    p.add_argument("--output", type=Path, help="output .blend (one input) or folder")
    p.add_argument("--in-place", action="store_true", help="overwrite the input, after a "
                   ".blend1 backup")
    p.add_argument("--jobs", type=int, default=None, help="worker processes (default: all "
                   "cores when there are several drawings)")
    p.add_argument("--summary", type=Path, help="write a JSON summary here")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                   help="simplify on this Dask cluster (pip install 'sketchsimp[cluster]')")
    p.add_argument("--resume", action="store_true",
                   help="skip the .blend files whose output is already there")
    return p


def blend_files(given: list[Path]) -> list[Path]:
    """The files given, each folder among them as the .blend files in it (sorted; not
    the ``*_simplified.blend`` an earlier run wrote beside its inputs)."""
    out = []
    for path in given:
        if path.is_dir():
            out += sorted(p for p in path.glob("*.blend")
                          if p.is_file() and not p.stem.endswith("_simplified"))
        else:
            out.append(path)
    return out


def output_path(blend: Path, args, several: bool) -> Path:
    if args.in_place:
        return blend
    if args.output is None:
        return blend.with_name(blend.stem + "_simplified.blend")
    if several:
        return args.output / blend.name
    return args.output


def open_objects(blend: Path | None, args) -> list:
    """Open ``blend`` (None: the file already open) and its Grease Pencil objects to run."""
    if blend is not None:
        if blend.stat().st_size == 0:
            raise FileError(f"{blend}: empty file")
        try:
            bpy.ops.wm.open_mainfile(filepath=str(blend))
        except RuntimeError as exc:  # Blender's "Cannot read file ..." and the like
            reason = str(exc).strip().splitlines()[-1] if str(exc).strip() else "unreadable"
            raise FileError(f"{blend}: not a readable .blend ({reason})") from None
    wanted = {n for n in args.objects.split(",") if n}
    objects = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"
               and (not wanted or o.name in wanted)]
    name = str(blend) if blend else bpy.data.filepath
    if not objects:
        raise FileError(f"{name}: no Grease Pencil object"
                        + (f" named {', '.join(sorted(wanted))}" if wanted else ""))
    return objects


def writable_folder(folder: Path, what: str) -> None:
    """Raise UsageError unless a file can be created in ``folder`` (made if missing)."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise UsageError(f"{what} {folder} cannot be written: {exc.strerror or exc}") from None


def check_outputs(blends: list, args, several: bool) -> None:
    """The places the run will write, tried before any work: the output folder (or each
    output file's folder) and the summary's folder."""
    folders = {output_path(b, args, several).parent if b is not None else
               Path(bpy.data.filepath).parent for b in blends} if not (
        several and args.output is not None and not args.in_place) else {args.output}
    for folder in sorted(folders):
        writable_folder(folder, "output folder")
    if args.summary is not None:
        if args.summary.is_dir():
            raise UsageError(f"summary path {args.summary} is a folder")
        writable_folder(args.summary.parent, "summary folder")


def run_options(args, frames_mode: str) -> SimpleNamespace:
    return SimpleNamespace(scope="CURRENT" if frames_mode == "current" else "ALL",
                           layers=args.layers.upper(), output="LAYER", hide_source=True,
                           as_curve=False, fill_regions=args.fill_regions, stable=args.stable)


def send_drawings(blend: Path | None, args, addon, cluster, frames_mode, frame_range) -> int:
    """Read every drawing of ``blend`` and send it to the cluster; how many were sent
    (``addon``: the add-on package, its modules loaded)."""
    sent = 0
    for ob in open_objects(blend, args):
        gathered = addon.read.gather_drawings(ob, run_options(args, frames_mode),
                                             bpy.context.scene.frame_current,
                                             addon.records.RunReport(), frame_range)
        for p in gathered.prepared:
            cluster.submit(p.sketch)
            sent += 1
    return sent


def process(blend: Path | None, args, params, addon, frames_mode, frame_range,
            engine=None, pool=None) -> dict:
    objects = open_objects(blend, args)
    scene = bpy.context.scene
    row = {"file": str(blend), "drawings": 0, "strokes_in": 0, "strokes_out": 0,
           "skipped": [], "objects": {}}
    for ob in objects:
        options = run_options(args, frames_mode)
        report, results = addon.run.simplify_object(ob, options, params, scene.frame_current,
                                                    jobs=args.jobs, frame_range=frame_range,
                                                    engine=engine, pool=pool)
        for r in results:
            frames = ",".join(str(f.frame_number) for f in r.frames)
            print(f"  {ob.name} / {r.layer.name} frame {frames}: {len(r.chosen)} -> "
                  f"{len(r.new.knots)} strokes", flush=True)
        addon.write.write_results(ob, options, results, bpy.context)
        row["objects"][ob.name] = {"drawings": report.drawings, "strokes_in": report.strokes_in,
                                   "strokes_out": report.strokes_out}
        for key in ("drawings", "strokes_in", "strokes_out"):
            row[key] += getattr(report, key)
        row["skipped"] += [f"{ob.name}: {s}" for s in report.skipped]
    return row


def main() -> int:
    args = parser().parse_args(script_argv(sys.argv))
    sys.path.insert(0, str(ROOT / "scripts"))
    from extension import load_extension

    load_extension()  # the repository as the extension package, nothing registered
    import sketchsimp.sketchsimp_addon as addon
    from sketchsimp.core import SimplifyParams, SketchError
    from sketchsimp.core.parallel import default_jobs, local_pool
    from sketchsimp.sketchsimp_addon import read, records, run, write  # noqa: F401 (loaded)

    t0 = time.perf_counter()
    cluster = None
    pools = contextlib.ExitStack()
    try:
        frames_mode, frame_range = parse_frames(args.frames)
        given = {k: getattr(args, k) for k in ("epsilon", "alpha", "samples")}
        params = SimplifyParams(**{k: v for k, v in given.items() if v is not None})
        if args.jobs is not None and args.jobs < 1:
            raise UsageError(f"--jobs must be at least 1, got {args.jobs}")
        blends = blend_files(args.blend) or ([None] if bpy.data.filepath else [])
        if not blends:
            raise UsageError("no .blend file given" if not args.blend else
                             f"no .blend file in {', '.join(map(str, args.blend))}")
        if args.resume and args.in_place:
            raise UsageError("--resume cannot tell finished files when writing in place")
        # outputs named as for every file given (a folder is several, whatever it holds)
        several = len(blends) > 1 or any(b.is_dir() for b in args.blend)
        failed: list[dict] = []

        def fail(blend, reason: str) -> None:
            print(f"batch_simplify: {reason}", file=sys.stderr, flush=True)
            failed.append({"file": str(blend), "reason": reason})

        for blend in blends:
            if blend is not None and not blend.is_file():
                fail(blend, f"{blend}: no such file")
        blends = [b for b in blends if b is None or b.is_file()]
        check_outputs(blends, args, several)
        if args.resume:
            done = [b for b in blends if b is not None and output_path(b, args, several).is_file()]
            for b in done:
                print(f"{b}: done before, skipped", flush=True)
            blends = [b for b in blends if b not in done]
        engine = None
        if args.scheduler:
            from sketchsimp.core.cluster import ClusterRun

            cluster = ClusterRun(args.scheduler, params, regions=args.fill_regions)
            for blend in list(blends):  # every file in flight before the first is written
                try:
                    sent = send_drawings(blend, args, addon, cluster, frames_mode, frame_range)
                except FileError as exc:
                    fail(blend, str(exc))
                    blends.remove(blend)
                    continue
                print(f"{blend or bpy.data.filepath}: {sent} drawing(s) sent to "
                      f"{args.scheduler}", flush=True)

            def engine(sketches, regions):
                return [cluster.result(cluster.submit(s)) for s in sketches]
        # one pool of workers for every file, started while the first is read
        jobs = default_jobs() if args.jobs is None else args.jobs
        pool = pools.enter_context(local_pool(jobs)) if engine is None and jobs > 1 else None
        rows = []
        for blend in blends:
            print(f"{blend or bpy.data.filepath}:", flush=True)
            try:
                row = process(blend, args, params, addon, frames_mode, frame_range, engine,
                              pool)
                source = Path(bpy.data.filepath)
                target = output_path(source, args, several)
                if args.in_place:
                    shutil.copy2(source, source.with_suffix(".blend1"))
                bpy.ops.wm.save_as_mainfile(filepath=str(target), copy=not args.in_place)
            except FileError as exc:
                fail(blend, str(exc))
                continue
            except BrokenProcessPool as exc:  # a worker died (killed, out of memory)
                fail(blend, f"{blend or bpy.data.filepath}: a worker process died ({exc})")
                pools.close()  # the next file gets a new pool
                pool = pools.enter_context(local_pool(jobs))
                continue
            except Exception as exc:  # one bad file must not stop a farm's batch
                traceback.print_exc()
                fail(blend, f"{blend or bpy.data.filepath}: {type(exc).__name__}: {exc}")
                continue
            row["output"] = str(target)
            rows.append(row)
    except (UsageError, SketchError) as exc:
        print(f"batch_simplify: {exc}", file=sys.stderr)
        return 2
    finally:
        pools.close()
        if cluster is not None:
            cluster.close()
    seconds = time.perf_counter() - t0
    total = {k: sum(r[k] for r in rows) for k in ("drawings", "strokes_in", "strokes_out")}
    print(f"{len(rows)} file(s), {total['drawings']} drawing(s): {total['strokes_in']} strokes "
          f"-> {total['strokes_out']} in {seconds:.2f} s"
          + (f"; {len(failed)} file(s) failed" if failed else ""))
    for row in rows:
        for s in row["skipped"]:
            print(f"  skipped {s}")
    for f in failed:
        print(f"  failed {f['reason']}")
    if args.summary:
        args.summary.write_text(json.dumps({"files": rows, "failed": failed, **total,
                                            "seconds": seconds, "params": params.as_dict()},
                                           indent=2))
    return 1 if failed else 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)  # under Blender a plain exit would not carry the status
