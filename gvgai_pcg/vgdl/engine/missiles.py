"""Missile (RULES.md §2): a passive move of ``(int)(speed * 10)`` px along the sprite's own
orientation at every update but its first (Java's ``isFirstTick``), through the cooldown gate,
which with Java's cooldown (at least 1, and ``checks`` keeps it at its default) is always open.

A table group of Missiles is updated whole: each sprite's update touches only itself. Its
``fresh`` column marks the sprites whose first update is still to come: level sprites at tick 0,
and a sprite created during play, whose first update is its group's next update (this tick's if
the group has not been updated yet, as Java appends it to a list not visited yet).
"""

from __future__ import annotations

from gvgai_pcg.games.geometry import direction_dx, direction_dy
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import TableGroup


def missile(frame: Frame, group: TableGroup) -> None:
    """One update of every live Missile of ``group``: ``lastrect := rect``, then move (not on the
    first update)."""
    types = frame.layout.plan.types
    table = frame.entry(group.key)
    alive, fresh, ori = table.get("alive"), table.get("fresh"), table.get("ori")
    step = lookup(tuple(types[name].step_px for name in group.kinds), table.get("kind"))
    distance = step * (alive & ~fresh)
    x, y = table.get("x"), table.get("y")
    table.update(
        {
            "lastx": x,
            "lasty": y,
            "x": x + distance * direction_dx(ori),
            "y": y + distance * direction_dy(ori),
            "fresh": fresh & ~alive,
        }
    )
