"""Every other sprite's update, type by type in Java's update order (reverse drawing order).

Grid types never change on their own (nor do Immovable tables); spawners, a grid of them or a
table, create sprites (``spawn``). A table that a ``bounceForward`` pushes saves its positions
(Java's ``preMovement``: ``lastrect := rect``), which a ``stepBack`` or ``undoAll`` of the pushed
sprites goes back to; in a game with an ``undoAll``, every still table and record does (one made
by a transform starts with its source's last position, which Java's next update forgets). A
table group is updated whole, at the first of its kinds in that order: its classes' updates touch
only the sprite itself, and its draws are keyed by slot (``layout``'s draw-key rule), so the
order of its sprites within the phase changes nothing.
"""

from __future__ import annotations

import torch

from gvgai_pcg.games import rng
from gvgai_pcg.games.geometry import NONE, direction_dx, direction_dy
from gvgai_pcg.vgdl.engine.flicker import table_flicker
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import FLICKERS, Layout, TableGroup
from gvgai_pcg.vgdl.engine.missiles import missile, per_kind
from gvgai_pcg.vgdl.engine.spawn import spawn_point, table_spawn_point
from gvgai_pcg.vgdl.layout import GRID, RECORD, TABLE

DIRECTIONS = 4  # RandomNPC draws one of the four base directions
# Table classes whose kernels save the start of the tick (``lastx, lasty``) themselves.
SELF_SAVING = frozenset({"RandomNPC", "Missile"})


def update_npcs(frame: Frame) -> None:
    layout = frame.layout
    done: set[str] = set()
    saved = saved_entries(layout)
    for name in layout.plan.update_order:
        if name in layout.avatars or name not in layout.places:
            continue
        place = layout.places[name]
        if place.representation == TABLE and place.key not in done:
            done.add(place.key)
            group = layout.group(place.key)
            if group.java_class == "RandomNPC":
                random_npc(frame, group)
            elif group.java_class == "Missile":
                missile(frame, group)
            elif group.java_class in FLICKERS:
                table_flicker(frame, group)
            elif group.java_class == "SpawnPoint":
                table_spawn_point(frame, group)
            if place.key in saved:
                pre_movement(frame, place.key)
        elif place.representation == RECORD:
            if name in saved:
                pre_movement(frame, name)
            if layout.plan.types[name].java_class in FLICKERS:
                flicker(frame, name)
        elif place.representation == GRID and layout.plan.types[name].java_class == "SpawnPoint":
            spawn_point(frame, name)


def saved_entries(layout: Layout) -> frozenset[str]:
    """The tables and records whose update saves their positions here: those a ``bounceForward``
    pushes (``checks``: of classes that never move by themselves) and, in a game with an
    ``undoAll``, every table and record whose class kernel does not (RandomNPC, Missile and the
    avatars save their own)."""
    saved = {
        layout.places[name].key
        for rule in layout.plan.pairs
        if rule.name == "bounceForward"
        for name in rule.firsts
        if name in layout.places and layout.places[name].representation == TABLE
    }
    if any(rule.name == "undoAll" for rule in layout.plan.pairs):
        saved.update(group.key for group in layout.tables if group.java_class not in SELF_SAVING)
        saved.update(name for name in layout.records if name not in layout.avatars)
    return frozenset(saved)


def pre_movement(frame: Frame, key: str) -> None:
    """``lastrect := rect`` for every sprite of table ``key``."""
    table = frame.entry(key)
    table.update({"lastx": table.get("x"), "lasty": table.get("y")})


def random_npc(frame: Frame, group: TableGroup) -> None:
    """RandomNPC (RULES.md §2): hold ``prev`` for ``cons`` updates, then draw a direction; move
    ``step`` px through the cooldown gate (a move undone later still resets it)."""
    types = frame.layout.plan.types
    table = frame.entry(group.key)
    kind, alive = table.get("kind"), table.get("alive")
    cons = per_kind(tuple(int(types[name].values["cons"]) for name in group.kinds), kind)
    cooldown = per_kind(tuple(max(1, int(types[name].values["cooldown"])) for name in group.kinds), kind)
    step = per_kind(tuple(types[name].step_px for name in group.kinds), kind)
    counter, prev = table.get("counter"), table.get("prev")
    drawn = rng.randint(frame.value("seed"), frame.value("tick"), table.get("draw"), group.stream, DIRECTIONS)
    draw = counter >= cons
    direction = torch.where(draw, drawn, prev)
    counter = torch.where(draw, torch.zeros_like(counter), counter + 1)
    lastmove = table.get("lastmove") + 1
    move = alive & (direction != NONE) & (lastmove >= cooldown)
    x, y = table.get("x"), table.get("y")
    distance = move * step
    table.update(
        {
            "lastx": x,
            "lasty": y,
            "x": x + distance * direction_dx(direction),
            "y": y + distance * direction_dy(direction),
            "lastmove": torch.where(move, torch.zeros_like(lastmove), lastmove),
            "counter": torch.where(alive, counter, table.get("counter")),
            "prev": torch.where(alive, direction, prev),
        }
    )


def flicker(frame: Frame, name: str) -> None:
    """Flicker (RULES.md §2): killed once its age exceeds ``limit``, then one older."""
    record = frame.entry(name)
    alive, age = record.get("alive"), record.get("age")
    limit = int(frame.layout.plan.types[name].values["limit"])
    frame.mark_killed(name, alive & (age > limit))
    record.set("age", age + alive)
