"""Command line.

    python -m core INPUT -o OUTPUT.svg [--epsilon E] [--stats STATS.json]
    python -m core inspect SKETCH [SKETCH ...] [--json]
    python -m core batch IN_DIR OUT_DIR [--jobs N] [--epsilon E] [--scap] [--summary S.json]

INPUT is .svg or .scap; OUTPUT is .svg (one <path> per output stroke) or .scap, in the
input's coordinates. Errors print one line and exit with status 1 (2 for bad usage).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..sketch import SketchError


def inspect_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m core inspect",
                                description="Print the base complex of sketch files.")
    p.add_argument("sketch", nargs="+", help=".svg or .scap file(s)")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    return p


def simplify_parser() -> argparse.ArgumentParser:
    from ..params import SimplifyParams

    d = SimplifyParams()
    p = argparse.ArgumentParser(
        prog="python -m core",
        description="Simplify a rough sketch into few long smooth strokes "
                    "(subcommand: 'inspect SKETCH' prints its base complex).")
    p.add_argument("input", help="rough sketch, .svg or .scap")
    p.add_argument("-o", "--output", required=True, help="where to write, .svg or .scap")
    p.add_argument("--epsilon", type=float, default=d.epsilon,
                   help=f"how far to simplify: largest shape change merged (default {d.epsilon})")
    p.add_argument("--alpha", type=float, default=d.alpha,
                   help=f"stroke bundle width as a fraction of the diagonal (default {d.alpha})")
    p.add_argument("--samples", type=int, default=d.samples,
                   help=f"Fourier descriptor samples N (default {d.samples})")
    p.add_argument("--stats", help="write counts and timings to this JSON file")
    return p


def batch_parser() -> argparse.ArgumentParser:
    from ..parallel import default_jobs
    from ..params import SimplifyParams

    p = argparse.ArgumentParser(prog="python -m core batch",
                                description="Simplify every .svg/.scap sketch in a folder.")
    p.add_argument("in_dir", type=Path, help="folder of .svg/.scap sketches")
    p.add_argument("out_dir", type=Path, help="folder for the results (made if missing)")
    p.add_argument("--jobs", type=int, default=default_jobs(),
                   help="worker processes (default: every core)")
    p.add_argument("--epsilon", type=float, default=SimplifyParams().epsilon,
                   help="how far to simplify (default %(default)s)")
    p.add_argument("--scap", action="store_true", help="write .scap instead of .svg")
    p.add_argument("--summary", type=Path, help="write counts and seconds to this JSON file")
    return p


def run_simplify(args: argparse.Namespace) -> None:
    from ..io.files import read_sketch, write_sketch
    from ..params import SimplifyParams
    from ..simplify import simplify

    out = Path(args.output)
    if out.suffix.lower() not in (".svg", ".scap"):
        raise SketchError(f"{out}: unknown output format {out.suffix!r} (use .svg or .scap)")
    params = SimplifyParams(epsilon=args.epsilon, alpha=args.alpha, samples=args.samples)
    result = simplify(read_sketch(args.input), params)
    write_sketch(result.to_sketch(), out)
    before, after = result.counts["before"], result.counts["after"]
    print(f"{args.input}: {before['strokes']} strokes -> {after['strokes']} in "
          f"{result.timings['total']:.2f} s, written to {out}")
    if args.stats:
        stats = {"input": str(args.input), "output": str(out), "params": params.as_dict(),
                 "counts": result.counts, "cleaning": result.cleaning.as_dict(),
                 "merges": len(result.history),
                 "timings": {k: round(v, 6) for k, v in result.timings.items()}}
        Path(args.stats).write_text(json.dumps(stats, indent=2))


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    try:
        if argv and argv[0] == "inspect":
            from .inspection import run
            args = inspect_parser().parse_args(argv[1:])
            run(args.sketch, args.json)
        elif argv and argv[0] == "batch":
            from ..params import SimplifyParams
            from .batch import batch
            args = batch_parser().parse_args(argv[1:])
            return batch(args.in_dir, args.out_dir, SimplifyParams(epsilon=args.epsilon),
                         args.jobs, ".scap" if args.scap else ".svg", args.summary)
        else:
            run_simplify(simplify_parser().parse_args(argv))
        return 0
    except SketchError as exc:
        print(f"python -m core: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        print(f"python -m core: {exc.filename or ''}: {exc.strerror or exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
