"""Speed as ratios against a pinned commit, both run here in one invocation, interleaved.

    python scripts/bench_against.py [--against 8618027] [--arm NAME=OPTIONS ...]
                                    [--every 5] [--largest 3] [--sizes 10000]
                                    [--data DIR] [--only PATTERN] [--json FILE]

Shared machines change speed two- to fourfold in a day, so a time alone says little. Every
figure here is this checkout against the commit ``--against``, run from a ``git worktree``
of it (made under ``.bench/``, kept for the next run) in the same invocation: sketch by
sketch, this tree then the commit, then the commit then this tree, each run a fresh
process, the best of the two rounds each. The machine's pace (a plain Python loop) is
printed for information only.

Arms: ``this`` (this checkout at its defaults) and, for the commit, one arm per
``--arm NAME=OPTIONS`` (``SimplifyParams`` fields as ``key=value,...``; by default
``pen=lines=pen`` and ``default=`` for 8618027, whose default stage was the complex one).

Figures, per arm: the fresh-run median over every ``--every``-th real sketch of
``../shared/data``; the ``--largest`` sketches (by points) summed; a slider step (replays
at 0.95, 0.8 and 0.5 of the epsilon in turn on one result, the slowest) at the median;
and for each ``--sizes`` synthetic sketch (``bench_simplify.synthetic``) its time and the
peak memory of the process that ran it, with the growth exponent where two or more sizes
are given. Then each target of :data:`TARGETS` with its ratio and verdict.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

from bench_simplify import machine_pace  # noqa: E402

DATA = ROOT.parent / "shared" / "data"
PINNED = "8618027"

#: the targets of issue 52: (figure, the arm it is against, the speed-up asked: the
#: commit's time over this tree's, at least this)
TARGETS = (
    ("fresh-run median", "pen", 1.6),
    ("largest sketches, summed", "pen", 1.5),
    ("slider step, median", "pen", 2.4),
    ("synthetic 10000, time", "pen", 1.5),
    ("fresh-run median", "default", 1.0),
    ("largest sketches, summed", "default", 1.0),
    ("slider step, median", "default", 1.0),
)

#: one measurement, in a fresh process importing ``core`` from ``root``: a fresh run, then
#: the slider steps on its result; seconds, and the process's peak memory (VmHWM)
PROBE = """
import json, resource, sys, time
root, scripts, path, options, steps = sys.argv[1:6]
sys.path[:0] = [root, scripts]
from core import SimplifyParams, Sketch, Stroke, read_sketch, simplify
options = json.loads(options)
if path.startswith("synthetic:"):
    from bench_simplify import synthetic
    sketch = Sketch([Stroke(p) for p in synthetic(int(path.split(":")[1]))])
    options["max_curves"] = None
else:
    sketch = read_sketch(path)
params = SimplifyParams(**options)
t0 = time.perf_counter()
result = simplify(sketch, params)
fresh = time.perf_counter() - t0
step = 0.0
for f in ([0.95, 0.8, 0.5] if steps == "1" else []):
    t0 = time.perf_counter()
    result.at(result.params.epsilon * f)
    step = max(step, time.perf_counter() - t0)
try:
    peak = int(open("/proc/self/status").read().split("VmHWM:")[1].split()[0]) / 1024
except OSError:
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"fresh": fresh, "step": step, "peak_mb": peak,
                  "strokes": len(result.strokes)}))
"""


def worktree(commit: str) -> Path:
    """A ``git worktree`` of ``commit`` under ``.bench/`` (made once, then reused)."""
    sha = subprocess.run(["git", "rev-parse", "--verify", f"{commit}^{{commit}}"], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout.strip()
    path = ROOT / ".bench" / f"worktree-{sha[:12]}"
    if not (path / "core").is_dir():
        path.parent.mkdir(exist_ok=True)
        subprocess.run(["git", "worktree", "add", "--force", "--detach", str(path), sha],
                       cwd=ROOT, capture_output=True, text=True, check=True)
    return path


def parse_options(text: str) -> dict:
    """``key=value,...`` as SimplifyParams fields (numbers where they parse)."""
    options = {}
    for item in filter(None, text.split(",")):
        key, value = item.split("=", 1)
        try:
            options[key] = float(value) if "." in value else int(value)
        except ValueError:
            options[key] = value
    return options


def probe(root: Path, path: str, options: dict, steps: bool) -> dict:
    done = subprocess.run([sys.executable, "-c", PROBE, str(root), str(ROOT / "scripts"), path,
                           json.dumps(options), "1" if steps else "0"],
                          capture_output=True, text=True)
    if done.returncode != 0:
        return {"error": done.stderr.strip().splitlines()[-1] if done.stderr else "failed"}
    return json.loads(done.stdout.strip().splitlines()[-1])


def interleaved(arms: dict[str, tuple[Path, dict]], path: str, steps: bool) -> dict:
    """Each arm's best of two rounds on one sketch, the second round in reverse order."""
    rounds: dict[str, list[dict]] = {name: [] for name in arms}
    order = list(arms)
    for names in (order, order[::-1]):
        for name in names:
            root, options = arms[name]
            rounds[name].append(probe(root, path, options, steps))
    best = {}
    for name, rows in rounds.items():
        failed = [r for r in rows if "error" in r]
        if failed:  # a run that failed is reported, not timed
            best[name] = failed[0]
            continue
        best[name] = {key: min(r[key] for r in rows) for key in ("fresh", "step", "peak_mb")}
        best[name]["strokes"] = rows[0]["strokes"]
    return best


def sketches(data: Path, every: int, largest: int, only: str) -> tuple[list[Path], list[Path]]:
    """Every ``every``-th rough sketch of the data (sorted by path; none for 0), and the
    ``largest`` by points."""
    files = sorted(p for p in data.rglob("*.scap") if p.name != "full_fit.scap"
                   and only in str(p))

    def points(p: Path) -> int:
        return sum(1 for line in p.read_text().splitlines()
                   if line[:1] not in ("#", "@", "{", "}", "") and not line.startswith("\t#"))

    by_size = sorted(files, key=points, reverse=True)[:largest]
    return (files[::every] if every > 0 else []), by_size


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", default=PINNED, help="the pinned commit (default %(default)s)")
    ap.add_argument("--arm", action="append", metavar="NAME=OPTIONS",
                    help="an arm of the pinned commit: its name, then SimplifyParams fields "
                    "as key=value,... (default: pen=lines=pen and default=)")
    ap.add_argument("--every", type=int, default=5, help="every N-th real sketch (0: none)")
    ap.add_argument("--largest", type=int, default=3, help="the N largest real sketches")
    ap.add_argument("--sizes", default="10000", help="synthetic sizes ('' for none)")
    ap.add_argument("--data", type=Path, default=DATA)
    ap.add_argument("--only", default="", help="substring of the sketch paths to run")
    ap.add_argument("--json", type=Path, help="write every measurement here")
    args = ap.parse_args(argv)

    base = worktree(args.against)
    arms: dict[str, tuple[Path, dict]] = {"this": (ROOT, {})}
    for spec in args.arm or ["pen=lines=pen", "default="]:
        name, options = spec.split("=", 1)
        arms[name] = (base, parse_options(options))
    print(f"this checkout against {args.against} ({', '.join(list(arms)[1:])}), interleaved, "
          f"best of two; pace {machine_pace():.3f} s", flush=True)
    figures: dict[str, dict[str, float]] = {}
    rows = {}
    if args.data.is_dir():
        every, largest = sketches(args.data, args.every, args.largest, args.only)
        for label, group in (("sample", every), ("largest", largest)):
            for path in group:
                row = interleaved(arms, str(path), steps=label == "sample")
                rows[f"{label}:{path.relative_to(args.data)}"] = row
                print(f"  {label:7s} {str(path.relative_to(args.data))[:48]:48s} " + "  ".join(
                    f"{n} {r['fresh']:6.2f} s" if "fresh" in r else f"{n} {r['error']}"
                    for n, r in row.items()), flush=True)
        for name in arms:
            sample = [rows[f"sample:{p.relative_to(args.data)}"][name] for p in every]
            big = [rows[f"largest:{p.relative_to(args.data)}"][name] for p in largest]
            ok = [r for r in sample if "fresh" in r]
            if ok:  # a figure of no sketch is left out, not printed as nan
                figures.setdefault("fresh-run median", {})[name] = float(
                    np.median([r["fresh"] for r in ok]))
                figures.setdefault("slider step, median", {})[name] = float(
                    np.median([r["step"] for r in ok]))
            if any("fresh" in r for r in big):
                figures.setdefault("largest sketches, summed", {})[name] = float(
                    sum(r["fresh"] for r in big if "fresh" in r))
    else:
        print(f"no sketches at {args.data}: the real-sketch figures are skipped")
    sizes = [int(n) for n in args.sizes.split(",") if n]
    for n in sizes:
        row = interleaved(arms, f"synthetic:{n}", steps=False)
        rows[f"synthetic:{n}"] = row
        for name, r in row.items():
            figures.setdefault(f"synthetic {n}, time", {})[name] = r.get("fresh", np.nan)
            figures.setdefault(f"synthetic {n}, peak MB", {})[name] = r.get("peak_mb", np.nan)
        print(f"  synthetic {n:6d} " + "  ".join(
            f"{name} {r.get('fresh', np.nan):7.2f} s {r.get('peak_mb', np.nan):6.0f} MB"
            for name, r in row.items()), flush=True)
    if len(sizes) >= 2:
        for name in arms:
            t = [figures[f"synthetic {n}, time"][name] for n in sizes]
            figures.setdefault("growth exponent", {})[name] = float(
                np.polyfit(np.log(sizes), np.log(t), 1)[0])

    print(f"\n{'figure':32s} " + " ".join(f"{n:>10s}" for n in arms) + "   this is x faster than")
    for figure, by_arm in figures.items():
        timed = "MB" not in figure and "exponent" not in figure and by_arm["this"] > 0
        ratios = ", ".join(f"{n} {by_arm[n] / by_arm['this']:.2f}x" for n in arms
                           if n != "this") if timed else ""
        print(f"{figure:32s} " + " ".join(f"{by_arm[n]:10.3f}" for n in arms) + f"   {ratios}")
    print("\ntargets (the commit's time over this tree's):")
    for figure, arm, least in TARGETS:
        if figure not in figures or arm not in figures[figure] or not (
                figures[figure]["this"] > 0):  # not measured (no sketch, or no size)
            continue
        ratio = figures[figure][arm] / figures[figure]["this"]
        print(f"  {figure:28s} against {arm:8s} {ratio:5.2f}x  (target >= {least}x)  "
              f"{'met' if ratio >= least else 'NOT met'}")
    if args.json:
        args.json.write_text(json.dumps({"rows": rows, "figures": figures}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
