"""Simplifying many sketches at once in a pool of processes.

Sketches are independent, and plain data (numpy arrays) travels to worker processes
cheaply; only the output strokes come back. Workers are started with 'spawn', so they
import nothing but ``core`` (never Blender), whatever process starts them.

Inside Blender ``core`` is a subpackage of the extension (``bl_ext.<repo>.sketchsimp``),
a name that exists only in Blender's memory. A spawned worker first recreates that package
from its folder, by a few lines of source run through ``exec`` (a builtin, so nothing of
ours has to be importable before it runs), and can then unpickle the work function.
Spawned workers also re-run the parent's main script, which under Blender imports bpy (not
to be had outside Blender): while workers start, the main module's file is hidden.
"""

from __future__ import annotations

import multiprocessing
import os
import sys
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

from .engine import Recorded, Simplified, simplified
from .params import SimplifyParams
from .replay_cache import sketch_digest
from .simplify import from_record, simplify
from .sketch import Sketch, SketchError

__all__ = ["default_jobs", "local_pool", "simplify_all", "unique_sketches"]


def _simplify_one(args: tuple[Sketch, SimplifyParams, bool, float | None, Recorded | None]
                  ) -> Simplified | SketchError:
    sketch, params, regions, cover, recorded = args
    try:
        if recorded is not None:  # rebuilt from its merge record: no merge loop
            return simplified(from_record(sketch, replace(recorded.params,
                                                          epsilon=params.epsilon),
                                          list(recorded.merges), recorded.covers), regions)
        return simplified(simplify(sketch, params, cover=cover), regions,
                          record=cover is not None)
    except SketchError as exc:
        return exc


#: run in each worker: make the package that holds ``core`` importable under its name
_BOOTSTRAP = """
import importlib.util, sys, types
name, path = {name!r}, {path!r}
parts = name.split(".")
for i in range(1, len(parts)):
    sys.modules.setdefault(".".join(parts[:i]), types.ModuleType(".".join(parts[:i])))
spec = importlib.util.spec_from_file_location(name, path + "/__init__.py",
                                              submodule_search_locations=[path])
module = importlib.util.module_from_spec(spec)
sys.modules[name] = module
spec.loader.exec_module(module)
"""


def _worker_setup() -> tuple:
    """(initializer, args) that let a spawned worker import this module by its name."""
    package = __name__.rpartition(".core.")[0]
    if not package:  # imported as top-level ``core``: the child's sys.path finds it
        return None, ()
    source = _BOOTSTRAP.format(name=package, path=str(Path(__file__).resolve().parents[1]))
    return exec, (source, {})


@contextmanager
def _main_script_hidden() -> Iterator[None]:
    """Keep spawned workers from re-running the main script (a Blender script imports bpy)."""
    main = sys.modules.get("__main__")
    saved = {k: main.__dict__[k] for k in ("__file__", "__spec__") if main and k in main.__dict__}
    if main is not None:
        main.__dict__.pop("__file__", None)
        main.__spec__ = None
    try:
        yield
    finally:
        if main is not None:
            main.__dict__.update(saved)
            if "__spec__" not in saved:
                del main.__spec__


def _started() -> None:
    """Run once in each worker of :func:`local_pool` as it starts: importing this module
    (to unpickle it) imports ``core``, the part of a worker's start that costs."""


@contextmanager
def local_pool(jobs: int) -> Iterator[ProcessPoolExecutor]:
    """A pool of ``jobs`` worker processes for :func:`simplify_all`'s ``pool``, started
    now: each worker is spawned and has imported ``core`` while the caller goes on (a
    batch reads its first file meanwhile), and serves every later call until the block
    ends, rather than a pool started and stopped for each call (about 0.4 s on this
    2-core machine, most of it importing numpy, shapely and ``core`` in each worker).

    >>> with local_pool(2) as pool:
    ...     pool.submit(sum, [1, 2]).result()
    3
    """
    if jobs < 1:
        raise SketchError(f"jobs must be at least 1, got {jobs}")
    initializer, initargs = _worker_setup()
    with _main_script_hidden():  # spawned now, not on the first job
        pool = ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context(
            "spawn"), initializer=initializer, initargs=initargs)
        for _ in range(jobs):
            pool.submit(_started)
    with pool:
        yield pool


def default_jobs() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
               else (os.cpu_count() or 1))


def unique_sketches(sketches: list[Sketch]) -> tuple[list[int], list[int]]:
    """Identical sketches, found by content (:func:`core.replay_cache.sketch_digest`): the
    index of the first of each distinct sketch, and for every sketch the position of its
    own in that list.

    >>> from core import Sketch, Stroke
    >>> a, b = Sketch([Stroke([[0, 0], [1, 0]])]), Sketch([Stroke([[0, 0], [0, 1]])])
    >>> unique_sketches([a, b, Sketch([Stroke([[0, 0], [1, 0]])]), a])
    ([0, 1], [0, 1, 0, 0])
    """
    first: dict[str, int] = {}  # digest -> position among the distinct
    where, firsts = [], []
    for k, sketch in enumerate(sketches):
        digest = sketch_digest(sketch)
        if digest not in first:
            first[digest] = len(firsts)
            firsts.append(k)
        where.append(first[digest])
    return firsts, where


def simplify_all(sketches: list[Sketch], params: SimplifyParams, jobs: int = 1,
                 progress: Callable[[int, int, int], None] | None = None, regions: bool = False,
                 scheduler: str | None = None, connect_timeout: float = 20.0,
                 cover: float | None = None, records: list[Recorded | None] | None = None,
                 pool: ProcessPoolExecutor | None = None) -> list[Simplified | SketchError]:
    """What each sketch simplifies into, in order (with its fill regions if ``regions``);
    a sketch that cannot be simplified gives its :class:`SketchError` in its place.

    Identical sketches are simplified once, however they run: ``jobs`` > 1 uses that many
    local processes; ``scheduler`` (``tcp://host:port``) a Dask cluster instead
    (:mod:`core.cluster`), waiting up to ``connect_timeout`` seconds for it.
    ``progress(done, total, k)`` is called as each distinct sketch finishes, ``k`` its
    first index in ``sketches``. ``cover`` (local runs): each merge loop runs on to it
    and the result carries its :class:`~core.engine.Recorded`, for replays up to it.
    ``records`` (local runs), one or None per sketch: a sketch with one is rebuilt from it
    (:func:`core.simplify.from_record`) rather than run. ``pool``: a running
    :func:`local_pool` to run in, rather than starting ``jobs`` processes for this call.
    """
    if jobs < 1:
        raise SketchError(f"jobs must be at least 1, got {jobs}")
    firsts, where = unique_sketches(sketches)
    done: dict[int, Simplified | SketchError] = {}  # by index into firsts

    def finished(u: int, out: Simplified | SketchError) -> None:
        done[u] = out
        if progress is not None:
            progress(len(done), len(firsts), firsts[u])

    if scheduler is not None:
        from .cluster import ClusterRun

        with ClusterRun(scheduler, params, regions, connect_timeout) as run:
            keys = [run.submit(sketches[k]) for k in firsts]
            position = {key: u for u, key in enumerate(keys)}
            for key in run.as_completed(keys):
                finished(position[key], run.result(key))
        return [done[u] for u in where]
    work = [(sketches[k], params, regions, cover, records[k] if records else None)
            for k in firsts]
    if len(work) < 2 or (pool is None and jobs == 1):
        for u, item in enumerate(work):
            finished(u, _simplify_one(item))
    elif pool is not None:
        for u, result in enumerate(pool.map(_simplify_one, work)):
            finished(u, result)
    else:
        with local_pool(min(jobs, len(work))) as started:
            for u, result in enumerate(started.map(_simplify_one, work)):
                finished(u, result)
    return [done[u] for u in where]
