"""What simplifying one sketch gives back, as plain data: the one interface the local
pool (:mod:`core.parallel`) and the Dask runner (:mod:`core.cluster`, :mod:`core.remote`)
share. The runner never imports the pool; the pool reaches the runner only when it is
given a scheduler (and imports it then): no import circle."""

from __future__ import annotations

from dataclasses import dataclass

from .params import SimplifyParams
from .sketch import Region, Stroke

__all__ = ["Recorded", "Simplified", "simplified"]


@dataclass(frozen=True)
class Recorded:
    """What a run elsewhere sends back for replays at other epsilons: its resolved params,
    its merge record and the epsilon that reaches (:func:`core.simplify.from_record`
    rebuilds the result from them, exactly)."""

    params: SimplifyParams
    merges: tuple
    covers: float


@dataclass(frozen=True)
class Simplified:
    """What comes back of one sketch: the output strokes and, when asked for, its closed
    regions (:meth:`core.simplify.SimplifyResult.fill_regions`)."""

    strokes: list[Stroke]
    regions: list[Region]
    width: float  #: the bundle width used, in the sketch's units (d_eps)
    record: Recorded | None = None  #: when asked for: what replays need


def simplified(result, regions: bool, record: bool = False) -> Simplified:
    """The plain data of a result that crosses back to the caller (with its
    :class:`Recorded` when ``record``)."""
    return Simplified(result.strokes, result.fill_regions() if regions else [],
                      result.bundle_width,
                      Recorded(result.params, tuple(result.record), result.covers)
                      if record else None)
