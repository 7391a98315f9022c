"""Zelda's level editor (ACCEL's mutations): move the key or the door, add or remove an inner wall,
add or remove a monster; never the border walls, never a monster within ``MONSTER_CLEARANCE``
of the avatar (the generator puts monsters far from it). ``edit`` keeps only edits after which
the key and the door are still reachable (``checks.playability_problems``)."""

from __future__ import annotations

import numpy as np

from gvgai_pcg.games.editing import EditKind, Grid, apply_edit, choose, far_from, inner_box, move, place
from gvgai_pcg.levels.level import Level

MONSTERS = "123"
MONSTER_CLEARANCE = 2  # an added monster is more than this many cells (Manhattan) from the avatar


def move_key(grid: Grid, rng: np.random.Generator) -> bool:
    return move(grid, rng, "+", on=".", leave=".")


def move_door(grid: Grid, rng: np.random.Generator) -> bool:
    return move(grid, rng, "g", on=".", leave=".")


def add_wall(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, "w", on=".", where=inner_box(grid))


def remove_wall(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, ".", on="w", where=inner_box(grid))


def add_monster(grid: Grid, rng: np.random.Generator) -> bool:
    away = far_from(grid.find("A"), MONSTER_CLEARANCE)
    return place(grid, rng, choose(rng, MONSTERS), on=".", where=away)


def remove_monster(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, ".", on=MONSTERS)


KINDS: dict[str, EditKind] = {
    "move_key": move_key,
    "move_door": move_door,
    "add_wall": add_wall,
    "remove_wall": remove_wall,
    "add_monster": add_monster,
    "remove_monster": remove_monster,
}


def edit(level: Level, seed: int) -> Level:
    """``level`` with one of ``KINDS`` applied, drawn by ``seed`` (gvgai_pcg.games.editing)."""
    return apply_edit(level, seed, KINDS, "zelda")[1]
