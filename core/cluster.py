"""Simplifying many sketches on a Dask cluster: the engine behind ``--scheduler``.

A studio's roughs run to thousands of drawings; Dask distributed is the engine (its
scheduler and workers as Dask ships them, on a laptop, a farm's machines, or SLURM
through dask-jobqueue), not a task server of our own. The client sends each distinct
sketch as one task; the workers run :func:`core.remote.simplify_payload`, and need the
project's Python package, never Blender.

Invariants:

* results are those of the local run, exactly: the same ``simplify`` on the same arrays
  (tested against ``--jobs 1``, byte for byte);
* a task's key is the digest of its sketch and parameters (:func:`task_key`), so identical
  drawings (cycles, copied keyframes, a file submitted twice) are computed once;
* a worker that dies takes no result with it: the scheduler runs its tasks again on
  another worker (Dask's own bookkeeping; a task that has killed
  ``distributed.scheduler.allowed-failures`` workers is reported as failed, not retried for
  ever);
* a sketch that fails comes back as a :class:`~core.sketch.SketchError` in its place, by
  name, and the rest go on.

Dask is an optional extra (``pip install 'sketchsimp[cluster]'``), imported only here and
only when a scheduler is given; the Blender extension never ships it.
"""

from __future__ import annotations

import builtins
import hashlib
import types
from collections.abc import Iterator

from . import remote
from .engine import Simplified
from .params import SimplifyParams
from .replay_cache import sketch_digest
from .sketch import Region, Sketch, SketchError, Stroke

__all__ = ["ClusterRun", "payload", "task_key"]


def payload(sketch: Sketch, params: SimplifyParams, regions: bool) -> dict:
    """A sketch and its parameters as plain data for :func:`core.remote.simplify_payload`."""
    return {"strokes": [remote.plain_stroke(s) for s in sketch.strokes],
            "width": sketch.width, "height": sketch.height, "params": params.as_dict(),
            "regions": regions}


def task_key(sketch: Sketch, params: SimplifyParams, regions: bool) -> str:
    """The task's name on the cluster: the same for the same drawing and parameters."""
    h = hashlib.blake2b(digest_size=12)
    h.update(sketch_digest(sketch).encode())
    h.update(repr((sorted(params.as_dict().items()), regions)).encode())
    return f"sketchsimp-{h.hexdigest()}"


def _by_value(function):
    """A copy of ``function`` that belongs to no module: pickle cannot name it, so Dask
    (which tries pickle, then cloudpickle) sends its code. Pickled by reference it would be
    ``bl_ext.<repo>.sketchsimp.core.remote...``, a name only Blender has.
    (``cloudpickle.register_pickle_by_value`` is not enough: Dask pickles the whole task
    with pickle first, which names the function.)"""
    return types.FunctionType(function.__code__, {"__builtins__": builtins,
                                                  "__name__": "sketchsimp_task"},
                              function.__name__, function.__defaults__)


def _from_plain(out: dict) -> Simplified | SketchError:
    if "error" in out:
        return SketchError(out["error"])
    return Simplified([Stroke(**s) for s in out["strokes"]],
                      [Region(outline, holes) for outline, holes in out["regions"]],
                      out["width"])


class ClusterRun:
    """Sketches simplified on the Dask cluster at ``address``, one task per distinct sketch.

    ``submit`` returns a task's key at once; ``result`` waits for it; ``as_completed``
    yields keys as their tasks finish. Use as a context manager (closes the client).

    Args:
        address: the scheduler, e.g. ``tcp://10.0.0.5:8786``.
        params: the parameters of every sketch.
        regions: also return each sketch's closed regions.
        timeout: seconds to wait for the scheduler to answer.
    """

    def __init__(self, address: str, params: SimplifyParams, regions: bool = False,
                 timeout: float = 20.0) -> None:
        try:
            from distributed import Client
        except ImportError:
            raise SketchError("running on a cluster needs Dask: pip install "
                              "'sketchsimp[cluster]' (dask[distributed])") from None
        self.task = remote.simplify_payload
        if remote.__name__ != "core.remote":  # core is a subpackage here (in Blender)
            self.task = _by_value(remote.simplify_by_name)
        self.params, self.regions = params, regions
        try:
            self.client = Client(address, timeout=timeout)
        except (OSError, TimeoutError, ValueError) as exc:
            raise SketchError(f"no Dask scheduler answers at {address}: {exc}") from None
        self._futures: dict = {}

    def submit(self, sketch: Sketch) -> str:
        """Send ``sketch`` (once, whatever how often it is submitted); its task's key."""
        key = task_key(sketch, self.params, self.regions)
        if key not in self._futures:
            self._futures[key] = self.client.submit(
                self.task, payload(sketch, self.params, self.regions), key=key)
        return key

    def result(self, key: str):
        """The :class:`~core.engine.Simplified` of a submitted sketch, or its
        :class:`~core.sketch.SketchError`."""
        try:
            return _from_plain(self._futures[key].result())
        except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: this sketch, not the run
            return SketchError(f"failed on the cluster: {type(exc).__name__}: {exc}")

    def as_completed(self, keys: list[str]) -> Iterator[str]:
        """The distinct ``keys`` in the order their tasks finish."""
        from distributed import as_completed

        by_future = {self._futures[k]: k for k in dict.fromkeys(keys)}
        for future in as_completed(list(by_future)):
            yield by_future[future]

    def close(self) -> None:
        self.client.close()

    def __enter__(self) -> ClusterRun:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
