"""OngoingAvatar (RULES.md §2): a pressed direction turns it at once (reversal included), then it
moves ``step`` px along its orientation, from its second update on; it never stops."""

from __future__ import annotations

import torch

from gvgai_pcg.games.actions import move_direction
from gvgai_pcg.games.geometry import NONE, direction_dx, direction_dy
from gvgai_pcg.vgdl.engine.frame import Frame


def ongoing_avatar(frame: Frame, name: str, action: torch.Tensor) -> None:
    """Its cooldown is Java's default 1 (``checks`` refuses another), so the gate is always open."""
    avatar = frame.entry(name)
    alive, fresh = avatar.get("alive"), avatar.get("fresh")
    direction = move_direction(action)
    ori = torch.where(alive & (direction != NONE), direction, avatar.get("ori"))
    move = alive & ~fresh & (ori != NONE)
    step = frame.layout.plan.types[name].step_px
    x, y = avatar.get("x"), avatar.get("y")
    avatar.update(
        {
            "lastx": x,
            "lasty": y,
            "x": x + move * step * direction_dx(ori),
            "y": y + move * step * direction_dy(ori),
            "ori": ori,
            "fresh": fresh & ~alive,
        }
    )
