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

from gvgai_pcg.games.geometry import DIRECTION_DX, DIRECTION_DY, NONE, direction_dx, direction_dy
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import Layout, TableGroup


def missile(frame: Frame, group: TableGroup) -> None:
    """One update of every live Missile of ``group``: ``lastrect := rect``, ``lastmove += 1``,
    then move (not on the first update) where the gate is open. A value its kinds share (a
    cooldown, a step, the direction of kinds no rule turns) is a number, not a lookup."""
    layout = frame.layout
    types = layout.plan.types
    table = frame.entry(group.key)
    kind, alive, fresh, ori = (table.get(key) for key in ("kind", "alive", "fresh", "ori"))
    cooldowns = tuple(max(1, int(types[name].values["cooldown"])) for name in group.kinds)
    step = per_kind(tuple(types[name].step_px for name in group.kinds), kind)
    lastmove = table.get("lastmove") + alive
    move = alive & ~fresh
    if max(cooldowns) > 1:  # a live sprite's lastmove is at least 1: the gate of 1 is open
        move = move & (lastmove >= lookup(cooldowns, kind))
    if turned(layout, group.kinds):
        move = move & (ori != NONE)
        dx, dy = direction_dx(ori), direction_dy(ori)
    else:  # each kind keeps the direction it starts with (``layout``, ``creation``)
        defaults = tuple(layout.orientation[name] for name in group.kinds)
        if NONE in defaults:
            move = move & (ori != NONE)
        dx = per_kind(tuple(DIRECTION_DX[code] for code in defaults), kind)
        dy = per_kind(tuple(DIRECTION_DY[code] for code in defaults), kind)
    x, y = table.get("x"), table.get("y")
    distance = move * step
    table.update(
        {
            "lastx": x,
            "lasty": y,
            "x": _moved(x, distance, dx),
            "y": _moved(y, distance, dy),
            "lastmove": torch.where(move, torch.zeros_like(lastmove), lastmove),
            "fresh": fresh & ~alive,
        }
    )


def turned(layout: Layout, kinds: tuple[str, ...]) -> bool:
    """Whether a rule may turn sprites of ``kinds`` from the direction each kind starts with."""
    return any(
        rule.name == "reverseDirection" and set(rule.firsts) & set(kinds) for rule in layout.plan.pairs
    )


def shared_direction(layout: Layout, kinds: tuple[str, ...]) -> tuple[int, int] | None:
    """The unit ``(dx, dy)`` every sprite of ``kinds`` (a table's) moves along at every tick,
    where they share one that no rule turns; None otherwise."""
    if turned(layout, kinds):
        return None
    units = {
        (DIRECTION_DX[layout.orientation[name]], DIRECTION_DY[layout.orientation[name]]) for name in kinds
    }
    return units.pop() if len(units) == 1 else None


def per_kind(values: tuple[int, ...], kind: torch.Tensor) -> int | torch.Tensor:
    """``values[kind]``: the one value where the kinds share it."""
    return values[0] if len(set(values)) == 1 else lookup(values, kind)


def _moved(position: torch.Tensor, distance: torch.Tensor, unit: int | torch.Tensor) -> torch.Tensor:
    """``position + distance * unit``, with fewer ops for a unit the kinds share."""
    if isinstance(unit, torch.Tensor):
        return position + distance * unit
    if unit == 0:
        return position
    return position + distance if unit == 1 else position - distance
