"""``killIfFromAbove``: a first is killed by a second that came down onto it from above.

Java kills first ``a`` for a second ``b`` it overlaps iff ``a.lastrect.y > b.lastrect.y + 5``
(``b`` was higher at the start of the tick) and ``b.rect.y > b.lastrect.y`` (``b`` moved down
this tick); the score only when it fires, once per such second for an avatar (only disabled,
it stays a first) and once for any other sprite (killed, it is done).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gvgai_pcg.vgdl.engine.frame import Frame

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

ABOVE_PX = 5  # Java's margin: the second's last top edge more than 5 px above the first's


def kill_if_from_above(frame: Frame, rule: Rule) -> None:
    for first in rule.firsts:
        x, y = frame.xy(first)
        last_y = frame.entry(first.key).get("lasty")
        last_y = last_y.unsqueeze(-1) if last_y.dim() == 1 else last_y
        hits = None
        for second in rule.seconds:
            entry = frame.entry(second.key)
            sy, slast = entry.get("y"), entry.get("lasty")
            if sy.dim() == 1:
                sy, slast = sy.unsqueeze(-1), slast.unsqueeze(-1)
            came_down = (last_y.unsqueeze(-1) > slast.unsqueeze(-2) + ABOVE_PX) & (sy > slast).unsqueeze(-2)
            meets = frame.overlap_matrix(x, y, first.aligned, first, second) & came_down
            count = meets.sum(-1)
            hits = count if hits is None else hits + count
        assert hits is not None
        hits = hits * frame.eligible(first)
        touched = hits > 0
        frame.kill(first, touched)
        applied = hits if first.key in frame.layout.avatars else touched.long()
        frame.add_score(rule.score * applied.sum(-1))
