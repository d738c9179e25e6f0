"""The plain records a run hands on: what was read of a drawing (:class:`Prepared`), what
replaces it (:class:`DrawingResult`), and what the run did (:class:`RunReport`)."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..core import (
    Sketch,
)
from .convert import (
    Plane,
)
from .drawing import DrawingData, NewStrokes

__all__ = [
    "DrawingResult", "Prepared", "RunReport",
]


@dataclass
class RunReport:
    drawings: int = 0
    strokes_in: int = 0
    strokes_out: int = 0
    seconds: float = 0.0
    skipped: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: the bundle width each drawing was simplified with, in its layer's units (d_eps)
    widths: list[float] = field(default_factory=list)
    #: result layers of an earlier run whose sources this run simplifies again: rewritten,
    #: not sources themselves (information, not a warning)
    rewritten: list[str] = field(default_factory=list)

    def message(self) -> str:
        text = (f"Simplified {self.drawings} drawing(s): {self.strokes_in} strokes -> "
                f"{self.strokes_out} in {self.seconds:.2f} s")
        if self.widths:
            low, high = min(self.widths), max(self.widths)
            text += (f", bundle width {low:.3g}" if f"{low:.3g}" == f"{high:.3g}" else
                     f", bundle width {low:.3g} to {high:.3g}")
        if self.skipped:
            text += "; skipped " + ", ".join(self.skipped)
        if self.rewritten:
            text += "; rewrote " + ", ".join(f"'{name}'" for name in self.rewritten)
        if self.notes:
            text += "; " + ", ".join(self.notes)
        return text


@dataclass
class DrawingResult:
    """One simplified drawing: where it came from and what replaces it."""

    layer: object
    frames: list  # every keyframe showing the drawing
    chosen: list[int]  # the strokes simplified
    new: NewStrokes
    fills: NewStrokes | None = None  # its closed regions, when asked for


@dataclass
class Prepared:
    """A drawing ready for the core: where it came from, what was read of it, the strokes
    chosen, its plane, and the sketch made of them on that plane."""

    layer: object
    frames: list  # every keyframe showing the drawing
    data: DrawingData
    chosen: list[int]
    plane: Plane
    sketch: Sketch
