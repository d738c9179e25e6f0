"""Fuzz ``core.simplify`` with random and adversarial sketches (``make fuzz``).

    python scripts/fuzz.py [--examples 10000] [--only KIND] [--seed S]

The examples are shared among the kinds of ``tests/fuzz_sketches.py`` (a long stroke of
100,000 points gets a hundredth of a share). Per kind: how many sketches were simplified,
how many refused with the documented SketchError, and the first failure (any other
exception or a broken invariant), shrunk by hypothesis. Exits 1 if anything failed.
"""

from __future__ import annotations

import argparse
import sys
import time
import traceback
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from fuzz_sketches import KINDS, check, fuzz_settings  # noqa: E402
from hypothesis import given, seed  # noqa: E402

from core import SimplifyParams  # noqa: E402


def fuzz_kind(kind: str, examples: int, rng_seed: int, params: SimplifyParams | None = None
              ) -> tuple[Counter, str | None]:
    strategy, _ = KINDS[kind]
    outcomes: Counter = Counter()

    @seed(rng_seed)
    @fuzz_settings(examples)
    @given(strategy)
    def run(strokes):
        outcomes[check(strokes, params)] += 1

    try:
        run()
    except Exception:  # report it and go on with the other kinds
        return outcomes, traceback.format_exc(limit=-3)
    return outcomes, None


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=10_000, help="in all, shared by kind")
    ap.add_argument("--only", default="", help="substring of the kinds to run")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    kinds = [k for k in KINDS if args.only in k]
    shares = sum(KINDS[k][1] for k in kinds)
    print(f"{'kind':32s} {'examples':>8s} {'simplified':>10s} {'refused':>8s} {'failed':>6s} "
          f"{'seconds':>8s}")
    failures = {}
    total = Counter()
    for kind in kinds:
        n = max(2, round(args.examples * KINDS[kind][1] / shares))
        t0 = time.perf_counter()
        outcomes, failure = fuzz_kind(kind, n, args.seed)
        failed = int(failure is not None)
        if failure:
            failures[kind] = failure
        total.update(outcomes)
        total["failed"] += failed
        print(f"{kind:32s} {n:8d} {outcomes['simplified']:10d} {outcomes['refused']:8d} "
              f"{failed:6d} {time.perf_counter() - t0:8.1f}", flush=True)
    print(f"\n{sum(total.values())} sketches run (shrinking included): {total['simplified']} "
          f"simplified, {total['refused']} refused with SketchError, {total['failed']} kinds "
          "failed")
    for kind, text in failures.items():
        print(f"\n--- {kind} ---\n{text}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
