"""Command line: a thin layer over the library, with argparse subcommands.

    python -m core [simplify] INPUT -o OUTPUT.svg [--epsilon E] [--alpha A] [--fill-gap G]
                                              [--stats S.json]
    python -m core inspect SKETCH [SKETCH ...] [--json]
    python -m core batch IN_DIR OUT_DIR [--jobs N | --scheduler tcp://HOST:PORT] [--resume]
                         [--epsilon E] [--scap] [--summary S.json]

INPUT is .svg or .scap; OUTPUT is .svg (one <path> per output stroke) or .scap, in the
input's coordinates. ``simplify`` is the subcommand taken when none is named. Defaults are
:class:`core.params.SimplifyParams`'s own. Errors print one line and exit with status 1
(2 for bad usage).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..io.files import read_sketch, write_sketch
from ..lines import PASSES
from ..parallel import default_jobs
from ..params import SimplifyParams
from ..simplify import simplify
from ..sketch import SketchError
from .batch import batch
from .inspection import run as run_inspect

__all__ = ["main", "parser"]

COMMANDS = ("simplify", "inspect", "batch")


def parser() -> argparse.ArgumentParser:
    d = SimplifyParams()
    top = argparse.ArgumentParser(
        prog="python -m core",
        description="Simplify rough sketches into few long smooth strokes.")
    sub = top.add_subparsers(dest="command", required=True, metavar="{simplify,inspect,batch}")

    one = sub.add_parser("simplify", help="simplify one sketch (the default subcommand)")
    one.add_argument("input", help="rough sketch, .svg or .scap")
    one.add_argument("-o", "--output", required=True, help="where to write, .svg or .scap")
    one.add_argument("--epsilon", type=float, default=d.epsilon,
                     help="how far to simplify: largest shape change merged (default "
                          "%(default)s)")
    one.add_argument("--alpha", type=_auto_or_number, default=d.alpha,
                     help="stroke bundle width as a fraction of the drawing's diagonal, or "
                          "'auto' (default: measured from the ink, 0.012 to 0.015, up to "
                          "0.03 for a sparse drawing whose result keeps the ink)")
    one.add_argument("--fill-gap", type=_auto_or_number, default=d.fill_gap,
                     help="widest ink-free band inside one bundle, as a fraction of the "
                          "drawing's diagonal: two lines with no wider band between their "
                          "inks may be one line drawn twice; 0 joins no such lines "
                          "(default 'auto': the ink's spacing)")
    one.add_argument("--samples", type=int, default=d.samples,
                     help="Fourier descriptor samples N (default %(default)s)")
    _skip_option(one)
    one.add_argument("--stats", help="write counts and timings to this JSON file")
    one.set_defaults(run=run_simplify)

    look = sub.add_parser("inspect", help="print the base complex of sketch files")
    look.add_argument("sketch", nargs="+", help=".svg or .scap file(s)")
    look.add_argument("--json", action="store_true", help="print JSON instead of a table")
    look.set_defaults(run=lambda args: run_inspect(args.sketch, args.json))

    many = sub.add_parser("batch", help="simplify every .svg/.scap sketch in a folder")
    many.add_argument("in_dir", type=Path, help="folder of .svg/.scap sketches")
    many.add_argument("out_dir", type=Path, help="folder for the results (made if missing)")
    many.add_argument("--jobs", type=int, default=default_jobs(),
                      help="worker processes (default: every core)")
    many.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                      help="run on this Dask cluster instead (pip install 'sketchsimp[cluster]')")
    many.add_argument("--connect-timeout", type=float, default=20.0, metavar="SECONDS",
                      help="how long to wait for the scheduler (default %(default)s)")
    many.add_argument("--resume", action="store_true",
                      help="skip the sketches whose output is already there")
    many.add_argument("--epsilon", type=float, default=d.epsilon,
                      help="how far to simplify (default %(default)s)")
    many.add_argument("--scap", action="store_true", help="write .scap instead of .svg")
    many.add_argument("--summary", type=Path, help="write counts and seconds to this JSON file")
    _skip_option(many)
    many.set_defaults(run=lambda args: batch(
        args.in_dir, args.out_dir, SimplifyParams(epsilon=args.epsilon, skip=tuple(args.skip)),
        args.jobs,
        ".scap" if args.scap else ".svg", args.summary, args.scheduler, args.resume,
        args.connect_timeout))
    return top


def _skip_option(command: argparse.ArgumentParser) -> None:
    """--skip, for simplify and batch."""
    command.add_argument("--skip", action="append", default=[], metavar="PASS",
                         choices=[name for name, _ in PASSES],
                         help="leave out this pass of the line stage (for ablations; "
                              "repeatable): " + ", ".join(name for name, _ in PASSES))


def _auto_or_number(text: str) -> float | str:
    """--alpha, --fill-gap: "auto" or a number."""
    if text == "auto":
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'auto' or a number, not {text!r}") from None


def run_simplify(args: argparse.Namespace) -> int:
    out = Path(args.output)
    if out.suffix.lower() not in (".svg", ".scap"):
        raise SketchError(f"{out}: unknown output format {out.suffix!r} (use .svg or .scap)")
    params = SimplifyParams(epsilon=args.epsilon, alpha=args.alpha, samples=args.samples,
                            fill_gap=args.fill_gap, skip=tuple(args.skip))
    result = simplify(read_sketch(args.input), params)
    write_sketch(result.to_sketch(), out)
    before, after = result.counts["before"], result.counts["after"]
    print(f"{args.input}: {before['strokes']} strokes -> {after['strokes']} in "
          f"{result.timings['total']:.2f} s, written to {out}")
    if args.stats:
        stats = {"input": str(args.input), "output": str(out),
                 "params": result.params.as_dict(),  # alpha as resolved: the width used
                 "bundle_width": result.bundle_width,
                 "counts": result.counts, "cleaning": result.cleaning.as_dict(),
                 "merges": len(result.history),
                 "timings": {k: round(v, 6) for k, v in result.timings.items()}}
        Path(args.stats).write_text(json.dumps(stats, indent=2))
    return 0


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] not in COMMANDS and argv[0] not in ("-h", "--help"):
        argv.insert(0, "simplify")  # python -m core INPUT -o OUTPUT
    args = parser().parse_args(argv)
    try:
        return args.run(args) or 0
    except SketchError as exc:
        print(f"python -m core: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        print(f"python -m core: {exc.filename or ''}: {exc.strerror or exc}", file=sys.stderr)
        return 1
