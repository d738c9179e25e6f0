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

import gc
import multiprocessing
import os
import sys
from collections import Counter, OrderedDict, deque
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

from .engine import Recorded, Simplified, simplified
from .params import SimplifyParams
from .replay_cache import ReplayCache, sketch_digest
from .simplify import from_record, simplify
from .sketch import Sketch, SketchError

__all__ = ["KEPT_POINTS", "KeptPool", "default_jobs", "local_pool", "simplify_all",
           "unique_sketches"]


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


def _spawned(jobs: int) -> ProcessPoolExecutor:
    """A pool of ``jobs`` spawned workers, each started now (importing ``core``)."""
    initializer, initargs = _worker_setup()
    with _main_script_hidden():  # spawned now, not on the first job
        pool = ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context(
            "spawn"), initializer=initializer, initargs=initargs)
        for _ in range(jobs):
            pool.submit(_started)
    return pool


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
    with _spawned(jobs) as pool:
        yield pool


def default_jobs() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
               else (os.cpu_count() or 1))


def unique_sketches(sketches: list[Sketch], digests: list[str] | None = None
                    ) -> tuple[list[int], list[int]]:
    """Identical sketches, found by content (:func:`core.replay_cache.sketch_digest`, or
    ``digests`` where the caller has them): the index of the first of each distinct
    sketch, and for every sketch the position of its own in that list.

    >>> from core import Sketch, Stroke
    >>> a, b = Sketch([Stroke([[0, 0], [1, 0]])]), Sketch([Stroke([[0, 0], [0, 1]])])
    >>> unique_sketches([a, b, Sketch([Stroke([[0, 0], [1, 0]])]), a])
    ([0, 1], [0, 1, 0, 0])
    """
    first: dict[str, int] = {}  # digest -> position among the distinct
    where, firsts = [], []
    for k, sketch in enumerate(sketches):
        digest = sketch_digest(sketch) if digests is None else digests[k]
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


#: the ink points (of the sketches simplified, not of the outputs) whose results a
#: :class:`KeptPool` holds between calls, over all its workers: a result with its base
#: complex and line-stage memo takes about 1 KB a point (0.2 to 0.7 KB pickled), so
#: about 400 MB at most; a 13-keyframe shot of product sketches is about 100,000 points
KEPT_POINTS = 400_000

#: merge records a kept worker holds (those sent to rebuild what it dropped): the add-on
#: keeps 512 of them; a worker needs one only until its result is rebuilt
KEPT_RECORDS = 64

#: a kept worker's cache of results, made on its first call (None in every other process)
_kept: ReplayCache | None = None
#: the results that cache had dropped when the worker last froze what it holds
_dropped = 0


class NeedsRecord:
    """A kept worker's answer for a sketch it no longer holds, whose merge record the
    caller keeps: send it, rather than run the merge loop again."""


def _kept_one(args: tuple[Sketch, SimplifyParams, bool, float | None, Recorded | None,
                          bool, int]) -> tuple[Simplified | SketchError | NeedsRecord, str]:
    """In a kept worker: one sketch through the worker's own :class:`ReplayCache`, and how
    it was had: ``"replayed"`` (from the result held here), ``"rebuilt"`` (from the record
    sent), or ``"ran"`` (the merge loop, on to ``cover``: the output carries its record)."""
    global _kept
    sketch, params, regions, cover, recorded, has_record, points = args
    if _kept is None or _kept.points != points:
        _kept = ReplayCache(size=1 << 30, records=KEPT_RECORDS, points=points)
    if recorded is not None:
        _kept.remember(sketch, params, recorded)
    elif has_record and not _kept.has_result(sketch, params):
        return NeedsRecord(), "asked"
    runs, rebuilds = _kept.runs, _kept.rebuilds
    try:
        result = _kept.result(sketch, params, cover=cover)
        how = ("ran" if _kept.runs > runs else "rebuilt" if _kept.rebuilds > rebuilds
               else "replayed")
        return simplified(result, regions, record=how == "ran" and cover is not None), how
    except SketchError as exc:
        return exc, "refused"
    finally:
        _settled(_kept)


def _settled(cache: ReplayCache) -> None:
    """Set what a kept worker holds (its results, their memos: hundreds of thousands of
    objects) aside from the cyclic garbage collector (``gc.freeze``). They live from call
    to call, and every full collection during a call would walk them all again; a result
    holds no reference cycles, so it is freed by reference counting when dropped, frozen
    or not. Where the cache dropped a result since the last call, what is frozen is first
    handed back and collected (``gc.unfreeze``, ``gc.collect``), so that a cycle a later
    change might bring is freed all the same."""
    global _dropped
    if cache.dropped != _dropped:
        gc.unfreeze()
        gc.collect()
        _dropped = cache.dropped
    gc.freeze()


class KeptPool:
    """Worker processes that keep what they simplified, for a slider over many drawings
    (Blender's redo panel on a shot): each distinct sketch goes back, call after call, to
    the worker that first simplified it, whose own :class:`ReplayCache` holds its result,
    so that a new epsilon is a replay there (with the line stage's memo: what did not
    change is not done again), not a rebuild of the base complex from a record.

    A sketch not yet placed goes to the first worker free (the largest first); the
    results kept are bounded by ``points`` of ink over all workers (:data:`KEPT_POINTS`),
    the least recently used dropped first. A worker that dropped a sketch's result asks
    for the record the caller keeps (``records``); a worker that died is started again.
    Each output equals ``simplify_all``'s. ``counts`` says how every sketch was had
    (:func:`_kept_one`), for tests and benchmarks.

    >>> from core import Sketch, Stroke, SimplifyParams
    >>> lines = [Stroke([[0, y], [50, y + 3], [100, y]]) for y in (0, 1, 40, 41)]
    >>> with KeptPool(2) as pool:
    ...     first = pool.simplify([Sketch(lines)], SimplifyParams(epsilon=0.02), cover=0.06)
    ...     again = pool.simplify([Sketch(lines)], SimplifyParams(epsilon=0.01))
    ...     len(first[0].strokes), len(again[0].strokes), sorted(pool.counts.items())
    (2, 2, [('ran', 1), ('replayed', 1)])
    """

    #: the sketches whose worker is remembered, the least recently sent forgotten first
    HOMES = 100_000

    def __init__(self, jobs: int, points: int = KEPT_POINTS) -> None:
        if jobs < 1:
            raise SketchError(f"jobs must be at least 1, got {jobs}")
        self.jobs, self.points = jobs, points
        self.counts: Counter[str] = Counter()
        self._workers = [_spawned(1) for _ in range(jobs)]
        self._home: OrderedDict[str, int] = OrderedDict()  # sketch digest -> its worker

    def __enter__(self) -> KeptPool:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Stop the workers (what they kept goes with them)."""
        for worker in self._workers:
            worker.shutdown(wait=True, cancel_futures=True)
        self._workers, self._home = [], OrderedDict()

    @property
    def alive(self) -> bool:
        return bool(self._workers)

    def start(self, sketches: list[Sketch], params: SimplifyParams, regions: bool = False,
              cover: float | None = None, records: list[Recorded | None] | None = None
              ) -> KeptRun:
        """The sketches sent to their workers; the :class:`KeptRun` says what came back."""
        if not self._workers:
            raise SketchError("this pool was closed")
        return KeptRun(self, sketches, params, regions, cover, records)

    def simplify(self, sketches: list[Sketch], params: SimplifyParams, regions: bool = False,
                 cover: float | None = None, records: list[Recorded | None] | None = None,
                 progress: Callable[[int, int, int], None] | None = None
                 ) -> list[Simplified | SketchError]:
        """What each sketch simplifies into, as :func:`simplify_all` says (``cover``,
        ``records`` and ``progress`` alike), each distinct sketch on its own worker."""
        run = self.start(sketches, params, regions, cover, records)
        while not run.done:
            for k in run.wait():
                if progress is not None:
                    progress(run.finished, run.total, k)
        return run.outputs

    def _send(self, w: int, args: tuple) -> Future:
        try:
            return self._workers[w].submit(_kept_one, args)
        except BrokenProcessPool:  # it died while idle: the sketch asks for its record
            self._restart(w)
            return self._workers[w].submit(_kept_one, args)

    def _placed(self, digest: str, w: int) -> None:
        self._home[digest] = w
        self._home.move_to_end(digest)
        while len(self._home) > self.HOMES:
            self._home.popitem(last=False)

    def _restart(self, w: int) -> None:
        """A new worker in place of worker ``w``, which died; nothing is homed on it."""
        self._workers[w].shutdown(wait=False, cancel_futures=True)
        self._workers[w] = _spawned(1)
        for digest in [d for d, home in self._home.items() if home == w]:
            del self._home[digest]


class KeptRun:
    """One call's sketches on a :class:`KeptPool`: each sketch placed before goes to its
    worker (two in flight, :meth:`_feed`), the others to whichever worker is free first.
    Made by :meth:`KeptPool.start`; :meth:`wait` advances it (an interface's timer can, a
    little at a time); :attr:`outputs` holds each sketch's output once it came (None
    before)."""

    #: a worker's own sketches in flight at once
    AHEAD = 2

    def __init__(self, pool: KeptPool, sketches: list[Sketch], params: SimplifyParams,
                 regions: bool, cover: float | None, records: list[Recorded | None] | None
                 ) -> None:
        self._pool, self._sketches = pool, sketches
        digests = [sketch_digest(sketch) for sketch in sketches]
        self._firsts, where = unique_sketches(sketches, digests)
        self._digests = [digests[k] for k in self._firsts]
        self._copies: list[list[int]] = [[] for _ in self._firsts]  # by distinct sketch
        for k, u in enumerate(where):
            self._copies[u].append(k)
        self._records = [records[k] if records else None for k in self._firsts]
        self._call = (params, regions, cover, max(1, pool.points // pool.jobs))
        sizes = [sum(len(s.points) for s in sketches[k].strokes) for k in self._firsts]
        self._homed: list[deque[int]] = [deque() for _ in range(pool.jobs)]
        self._free = deque(sorted((u for u, d in enumerate(self._digests)
                                   if d not in pool._home), key=lambda u: -sizes[u]))
        for u, digest in enumerate(self._digests):
            if digest in pool._home:
                self._homed[pool._home[digest]].append(u)
        self._done: dict[int, Simplified | SketchError] = {}
        # each sketch in flight, in the order sent: its worker, and that worker's pool
        self._running: dict[Future, tuple[int, int, ProcessPoolExecutor]] = {}
        self._died: Counter[int] = Counter()  # by sketch: how many workers died on it
        self._mourned: set[ProcessPoolExecutor] = set()  # workers whose death was counted
        self.outputs: list[Simplified | SketchError | None] = [None] * len(sketches)
        for w in range(pool.jobs):
            self._feed(w)

    @property
    def total(self) -> int:
        """How many distinct sketches the run simplifies."""
        return len(self._firsts)

    @property
    def finished(self) -> int:
        return len(self._done)

    @property
    def done(self) -> bool:
        return not self._running

    def wait(self, timeout: float | None = None) -> list[int]:
        """Wait up to ``timeout`` seconds (None: until one finishes) and take what came
        back: the index of each sketch (the first of identical ones) finished now."""
        now: list[int] = []
        if not self._running:
            return now
        finished, _ = wait(self._running, timeout, return_when=FIRST_COMPLETED)
        for future in finished:
            w, u, sent_to = self._running[future]
            if isinstance(future.exception(), BrokenProcessPool):  # killed, out of memory
                self._mourn(w, sent_to)
                del self._running[future]
                if self._died[u] < 2:  # each sketch it had goes again
                    self._send(w, u, with_record=True)
                    continue
                out, how = SketchError("the worker simplifying this drawing died twice "
                                       "(out of memory?)"), "refused"
            else:
                del self._running[future]
                out, how = future.result()
            self._pool.counts[how] += 1
            if isinstance(out, NeedsRecord):
                self._send(w, u, with_record=True)
                continue
            self._done[u] = out
            for k in self._copies[u]:
                self.outputs[k] = out
            now.append(self._firsts[u])
            self._feed(w)
        return now

    def _mourn(self, w: int, sent_to: ProcessPoolExecutor) -> None:
        """Worker ``w``'s death (its pool ``sent_to``) counted once, against the sketch it
        was running: the first sent of those it still had; the worker started again,
        unless a send found it dead first and did."""
        if sent_to in self._mourned:
            return
        self._mourned.add(sent_to)
        self._died[next(u for _, u, pool in self._running.values() if pool is sent_to)] += 1
        if self._pool._workers[w] is sent_to:
            self._pool._restart(w)

    def _in_flight(self, w: int) -> int:
        """How many sketches worker ``w`` has in flight."""
        return sum(x == w for x, _, _ in self._running.values())

    def cancel(self) -> None:
        """Take nothing more: what runs now finishes in its worker (and is kept there)."""
        self._homed = [deque() for _ in self._homed]
        self._free.clear()

    def _send(self, w: int, u: int, with_record: bool = False) -> None:
        self._pool._placed(self._digests[u], w)
        params, regions, cover, points = self._call
        recorded = self._records[u]
        args = (self._sketches[self._firsts[u]], params, regions, cover,
                recorded if with_record else None, recorded is not None, points)
        future = self._pool._send(w, args)  # which may start the worker again first
        self._running[future] = (w, u, self._pool._workers[w])

    def _feed(self, w: int) -> None:
        """Keep worker ``w`` busy: its own sketches sent ``AHEAD`` in flight (the next
        waits in its queue while the caller holds or writes what came back, rather than
        the worker waiting for the caller), else, with none in flight, one not yet placed
        (one at a time: the rest stay for whichever worker is free first)."""
        while self._in_flight(w) < self.AHEAD and self._homed[w]:
            self._send(w, self._homed[w].popleft())
        if not self._in_flight(w) and self._free:  # new to it: its record, if kept, along
            self._send(w, self._free.popleft(), with_record=True)
