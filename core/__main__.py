"""Command line: ``python -m core inspect SKETCH [--json]``."""

from __future__ import annotations

import argparse
import sys

from .sketch import SketchError


def inspect_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m core inspect",
                                description="Print the base complex of sketch files.")
    p.add_argument("sketch", nargs="+", help=".svg or .scap file(s)")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    return p


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] in ("-h", "--help"):
        print("usage: python -m core inspect SKETCH [--json]", file=sys.stderr)
        return 0 if argv else 2
    command, rest = argv[0], argv[1:]
    try:
        if command == "inspect":
            from .inspection import run
            args = inspect_parser().parse_args(rest)
            run(args.sketch, args.json)
            return 0
        print(f"python -m core: unknown command {command!r}", file=sys.stderr)
        return 2
    except SketchError as exc:
        print(f"python -m core: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
