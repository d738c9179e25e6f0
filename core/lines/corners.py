"""Pass 7 of :mod:`core.lines`: what the pen drew in one motion, cut by pass 1, joined
again. Pass 1 cut each stroke where it turned sharply, so that each leg could join its
own group; where the two legs' lines both end at that corner (within ``tuning.snap``
d_eps), the pen drew them as one stroke, and they join again there, the corner kept. So
with a stroke cut where it came back along its own ink: where pass 4 fitted the turn as
a ring of its own (that turn's ink alone) and the rest of the stroke as another line, the
next turn was not the same line drawn again but one beside it (a spiral), and the ring
opens where the stroke went on, joined to the rest. Each line end joins at most once,
where most input strokes turned from one onto the other (ties by the ends' numbers)."""

from __future__ import annotations

from collections import Counter
from dataclasses import replace

import numpy as np

from .chains import End, chain
from .work import Work

__all__ = ["run"]


def run(work: Work) -> Work:
    lines = work.current_lines()
    if len(lines) < 1 or len(work.pieces) < 2:
        return work.with_(lines=lines)
    line_of = np.full(len(work.pieces), -1)
    for k, line in enumerate(lines):
        line_of[list(line.members)] = k
    reach = work.tuning.snap * work.meet_d
    votes: Counter[tuple[End, End]] = Counter()
    same = (work.piece_stroke[1:] == work.piece_stroke[:-1]) & (
        work.piece_index[1:] == work.piece_index[:-1] + 1)
    for p in np.flatnonzero(same).tolist():
        a, b = int(line_of[p]), int(line_of[p + 1])
        if a < 0 or b < 0 or a == b:
            continue
        if any(lines[k].closed and lines[k].members != (q,) for k, q in ((a, p), (b, p + 1))):
            continue  # a ring drawn in more than one turn, or by other strokes too
        corner = work.pieces[p][-1]
        ends = []
        for k, ring_end in ((a, 1), (b, 0)):
            pts = lines[k].points
            gaps = np.hypot(*(pts[[0, -1]] - corner).T)
            # a ring of one turn opens at its seam: the end the stroke went on from
            e = ring_end if lines[k].closed else int(np.argmin(gaps))
            ends.append((k, e) if gaps[e] <= reach else None)
        if ends[0] is not None and ends[1] is not None:
            votes[tuple(sorted(ends))] += 1
    used: set[End] = set()
    joins = []
    for (x, y), _ in sorted(votes.items(), key=lambda kv: (-kv[1], kv[0])):
        if x in used or y in used:
            continue
        used.update((x, y))
        joins.append((x, y))
    if not joins:
        return work.with_(lines=lines)
    opened = {k for end in joins for k, _ in end if lines[k].closed}
    lines = [replace(ln, closed=False) if k in opened else ln for k, ln in enumerate(lines)]
    return work.with_(lines=chain(lines, joins, reach, work.h))
