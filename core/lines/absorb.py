"""Pass 6 of :mod:`core.lines`: lines that stand for ink another line already stands
for. A line lying wholly within ``tuning.absorb_reach`` d_eps of a longer line is left
out, its pieces counted as that line's, when it is shorter than ``tuning.crumb`` d_eps (a
hook at a stroke's end, cut off at its corner; a scrap at a junction), or when the two
inks leave no band free of ink wider than ``params.fill_gap`` between them
(:func:`core.lines.join.one_band`: a loose pass of the line that the fit split off, not
a line drawn close beside it); either only where the longer line keeps it in place, or
lies apart from the other lines, as a join must (:func:`core.lines.fit.regroup`): a
detail drawn short beside a long line is a line of its own. Not at epsilon 0."""

from __future__ import annotations

import numpy as np

from .fit import absorb_lines
from .join import one_band
from .work import Work

__all__ = ["run"]


def run(work: Work) -> Work:
    lines = work.current_lines()
    if not work.merged:
        return work.with_(lines=lines)
    # each line's, once: asked about pair by pair (lines are still their pieces' fits)
    widths, gaps = work.store("widths"), work.store("gaps")

    def band(k: int, o: int) -> bool:
        return len(one_band(lines, np.array([[k, o]]), work, widths, gaps)) == 1

    return work.with_(lines=absorb_lines(lines, work, band))
