"""Solarfox's level editor (ACCEL's mutations): add or remove a pill, move an enemy along its lane,
move the avatar. The generator's checks want exactly one top enemy (2) and one bottom enemy (1),
so an enemy is moved, never added or removed. The ship never stops once it flies (RULES.md §5.3)
and walls and the enemy lanes kill it, so the avatar only moves to a floor cell with a cell of
floor between it and them, as the generator's start (columns 4-5, rows 4-6) has.

``BOUNDS``: pills between one (the generator redraws a level without any) and the most the
generator can draw at d = 1 (its pill target P, each draw mirrored into two or four cells, so
up to P rounded up to a multiple of four); one enemy of each lane."""

from __future__ import annotations

import math

import numpy as np

from gvgai_pcg.games.editing import (
    Cell,
    CountBound,
    EditKind,
    Grid,
    apply_edit,
    choose,
    move,
    parameter_range,
    place,
)
from gvgai_pcg.games.solarfox.generator import parameters
from gvgai_pcg.levels.level import Level

PILLS = "bp"


def add_pill(grid: Grid, rng: np.random.Generator) -> bool:
    """A pill of a kind the level already has (a blib in a level without any)."""
    kinds = "".join(kind for kind in PILLS if grid.find(kind)) or "b"
    return place(grid, rng, choose(rng, kinds), on="+")


def remove_pill(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, "+", on=PILLS)


def move_enemy(grid: Grid, rng: np.random.Generator) -> bool:
    """The top (2) or the bottom (1) enemy to another cell of its own lane."""
    enemy = choose(rng, "21")
    cells = grid.find(enemy)
    if not cells:
        return False
    row = cells[0][0]
    return move(grid, rng, enemy, on=".", leave=".", where=lambda cell: cell[0] == row)


def move_avatar(grid: Grid, rng: np.random.Generator) -> bool:
    def clear(cell: Cell) -> bool:
        return 2 <= cell[0] <= grid.height - 3 and 2 <= cell[1] <= grid.width - 3

    return move(grid, rng, "A", on="+", leave="+", where=clear)


MIRRORS = 4  # cells one pill draw can fill with both symmetries (generator.place_pills)


def generator_bounds() -> tuple[CountBound, ...]:
    """What the generator can place, from its own ``parameters`` (the pill target P)."""
    _, most_pills = parameter_range(parameters, 0)
    return (
        CountBound("pills", PILLS, 1, MIRRORS * math.ceil(most_pills / MIRRORS)),
        CountBound("top enemies", "2", 1, 1),
        CountBound("bottom enemies", "1", 1, 1),
    )


BOUNDS = generator_bounds()

KINDS: dict[str, EditKind] = {
    "add_pill": add_pill,
    "remove_pill": remove_pill,
    "move_enemy": move_enemy,
    "move_avatar": move_avatar,
}


def edit(level: Level, seed: int) -> Level:
    """``level`` with one of ``KINDS`` applied, drawn by ``seed`` (gvgai_pcg.games.editing)."""
    return apply_edit(level, seed, KINDS, "solarfox", BOUNDS)[1]
