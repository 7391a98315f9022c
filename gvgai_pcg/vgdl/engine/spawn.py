"""SpawnPoint (RULES.md §2) held as a still grid: every spawner draws ``u ~ U[0, 1)`` at every
update, and at ticks ``tick % cooldown == 0`` (Java's ``start + tick`` with ``start`` = 0, the
first update of a level spawner) with ``u < prob`` it creates one ``stype`` sprite at its own
position, a sprite of a Missile or RandomNPC table (``checks`` refuses the rest).

A SpawnPoint with ``total`` is held in a table (``table_spawn_point``): each counts what it made
(``spawned``) and is killed by its own update once that reaches ``total`` (Java's ``counter``);
those are level spawners with ``prob`` 1 (``checks``), so nothing is drawn.

A spawner's draw is keyed by its cell (``layout.SPAWNER_ROW``) on the spawners' stream. A created
sprite takes a free slot (``creation``: slots hold no order); its ``born`` keeps Java's list order
(this tick's creations after every earlier sprite, in update order, then row-major) and ``fresh``
its first update, which is this tick's if its group is updated after the spawners.
"""

from __future__ import annotations

import torch

from gvgai_pcg.games import rng
from gvgai_pcg.games.geometry import CELL
from gvgai_pcg.vgdl.engine.creation import create
from gvgai_pcg.vgdl.engine.frame import Frame, reads_back
from gvgai_pcg.vgdl.engine.layout import SPAWNER_ROW, Layout, TableGroup


def spawn_point(frame: Frame, name: str) -> None:
    """One update of every spawner of grid type ``name``."""
    layout = frame.layout
    values = layout.plan.types[name].values
    made = str(values["stype"])
    grid = frame.grid(name)
    batch, height, width = grid.shape
    tick = frame.value("tick")
    cooldown = max(1, int(values["cooldown"]))
    due = (tick % cooldown == 0).unsqueeze(-1)
    placed = grid.reshape(batch, -1) > 0
    cells = torch.arange(height * width, device=grid.device)
    if reads_back(grid):
        # eagerly on the CPU, only the cells where some env has a spawner that is due: a draw
        # is keyed by its cell, so the others' draws change nothing (``reads_back``)
        cells = (placed & due).any(0).nonzero().flatten()
        if cells.numel() == 0:
            return
        placed = placed[:, cells]
    cell_x, cell_y = CELL * (cells % width), CELL * (cells // width)
    drawn = rng.uniform(frame.value("seed"), tick, cell_y * SPAWNER_ROW + cell_x, layout.spawner_stream)
    fires = placed & due & (drawn < float(values["prob"]))
    cells_x, cells_y = cell_x.expand(batch, -1), cell_y.expand(batch, -1)
    create(frame, made, fires.long(), cells_x, cells_y, _overflow(layout, name))


def table_spawn_point(frame: Frame, group: TableGroup) -> None:
    """One update of every spawner of a SpawnPoint table (see the module docstring), kind by
    kind; the creators in slot order, the level's list order (no spawner is made during play)."""
    types = frame.layout.plan.types
    table = frame.entry(group.key)
    tick = frame.value("tick").unsqueeze(-1)
    for code, name in enumerate(group.kinds):
        values = types[name].values
        mine = table.get("alive") & (table.get("kind") == code)
        fires = mine & (tick % max(1, int(values["cooldown"])) == 0)
        create(
            frame,
            str(values["stype"]),
            fires.long(),
            table.get("x"),
            table.get("y"),
            _overflow(frame.layout, name),
        )
        spawned = table.get("spawned") + fires
        table.set("spawned", spawned)
        total = int(values["total"])
        if total > 0:
            frame.mark_killed(group.key, mine & (spawned >= total))


def _overflow(layout: Layout, name: str) -> str:
    key = layout.places[str(layout.plan.types[name].values["stype"])].key
    return f"{layout.plan.path}: a SpawnPoint found the table {key!r} full (its capacity is the plan's)"
