"""pullWithIt (RULES.md §3, Java's PullWithIt): once a tick per first sprite, the first second it
overlaps in Java's list order pulls it by ``(int)(second.speed * 10)`` px (``(int)`` of the
first's own speed where that is 0) along the second's normalised displacement this tick, through
the first's cooldown gate (``lastmove >= cooldown``, shut if it moved itself this tick), which it
then shuts; its ``lastrect`` stays. A second that did not move gives no direction: no pull.

Implemented (``checks``) for a first held as a record that keeps ``lastmove`` (MovingAvatar) and
seconds in one Missile table, whose ``born`` column is Java's list order within a kind; the
line's rule on one pair only, so Java's once-a-tick guard is this rule's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.frame import Frame

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

# Java's list order of a pair's seconds: the second's leaf types in ``iSubTypes`` order, each in
# its list order (``born``, below 2^50).
KIND_ORDER = 1 << 50


def pull_with_it(frame: Frame, rule: Rule) -> None:
    layout = frame.layout
    first, second = rule.firsts[0], rule.seconds[0]
    avatar, table = frame.entry(first.key), frame.entry(second.key)
    x, y = frame.xy(first)
    meets = frame.overlap_matrix(x, y, first.aligned, first, second).squeeze(1)
    meets = meets & frame.eligible(first)
    group = layout.group(second.key)
    kind = table.get("kind")
    ranks = tuple(second.kinds.index(code) if code in second.kinds else 0 for code in range(len(group.kinds)))
    rank = lookup(ranks, kind)
    order = torch.where(meets, rank * KIND_ORDER + table.get("born"), torch.full_like(kind, 2**62))
    chosen = meets & (order == order.amin(-1, keepdim=True))  # born is unique: one slot at most
    dx = ((table.get("x") - table.get("lastx")) * chosen).sum(-1).to(torch.float64)
    dy = ((table.get("y") - table.get("lasty")) * chosen).sum(-1).to(torch.float64)
    own = int(float(layout.plan.types[first.key].values["speed"]))
    speeds = tuple(layout.plan.types[name].step_px or own for name in group.kinds)
    speed = (lookup(speeds, kind) * chosen).sum(-1).to(torch.float64)
    norm = torch.sqrt(dx * dx + dy * dy)
    safe = torch.where(norm > 0, norm, torch.ones_like(norm))
    vx, vy = dx / safe, dy / safe  # Java's Vector2d.normalise (a zero vector stays zero)
    cooldown = max(1, int(layout.plan.types[first.key].values["cooldown"]))
    lastmove = avatar.get("lastmove")
    pulled = meets.any(-1) & (norm > 0) & (lastmove >= cooldown)
    move_x, move_y = (vx * speed).trunc().to(x.dtype), (vy * speed).trunc().to(y.dtype)
    avatar.update(
        {
            "x": avatar.get("x") + move_x * pulled,
            "y": avatar.get("y") + move_y * pulled,
            "lastmove": torch.where(pulled, torch.zeros_like(lastmove), lastmove),
        }
    )
