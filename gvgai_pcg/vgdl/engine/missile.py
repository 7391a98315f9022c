"""Missile (RULES.md §2): a passive move of ``step`` px along the sprite's own orientation,
through the cooldown gate, from its second update on (Java's ``isFirstTick``)."""

from __future__ import annotations

import torch

from gvgai_pcg.games.geometry import NONE, direction_dx, direction_dy
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import TableGroup


def missile(frame: Frame, group: TableGroup) -> None:
    """Every present sprite: ``lastmove += 1``; its first update only clears the first-update
    flag; later ones move where ``lastmove >= cooldown`` and then reset it."""
    types = frame.layout.plan.types
    table = frame.entry(group.key)
    kind, alive, fresh, ori = (table.get(key) for key in ("kind", "alive", "fresh", "ori"))
    cooldown = lookup(tuple(max(1, int(types[name].values["cooldown"])) for name in group.kinds), kind)
    step = lookup(tuple(types[name].step_px for name in group.kinds), kind)
    lastmove = table.get("lastmove") + alive
    move = alive & ~fresh & (ori != NONE) & (lastmove >= cooldown)
    x, y = table.get("x"), table.get("y")
    distance = move * step
    table.update(
        {
            "lastx": x,
            "lasty": y,
            "x": x + distance * direction_dx(ori),
            "y": y + distance * direction_dy(ori),
            "lastmove": torch.where(move, torch.zeros_like(lastmove), lastmove),
            "fresh": fresh & ~alive,
        }
    )
