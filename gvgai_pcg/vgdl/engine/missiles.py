"""Missile (RULES.md §2): a passive move of ``(int)(speed * 10)`` px along the sprite's own
orientation at every update but its first (Java's ``isFirstTick``), through the cooldown gate:
``lastmove`` counts the updates, and a move needs ``lastmove >= cooldown`` and resets it (with
Java's default cooldown the gate is always open; Solarfox's enemies move every third tick).

A table group of Missiles is updated whole: each sprite's update touches only itself. Its
``fresh`` column marks the sprites whose first update is still to come: level sprites at tick 0,
and a sprite created during play, whose first update is its group's next update (this tick's if
the group has not been updated yet, as Java appends it to a list not visited yet).
"""

from __future__ import annotations

import torch

from gvgai_pcg.games.geometry import NONE, direction_dx, direction_dy
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import TableGroup


def missile(frame: Frame, group: TableGroup) -> None:
    """One update of every live Missile of ``group``: ``lastrect := rect``, ``lastmove += 1``,
    then move (not on the first update) where the gate is open."""
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
