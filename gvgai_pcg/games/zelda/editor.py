"""Zelda's level editor (ACCEL's mutations): move the key or the door, add or remove an inner wall,
add or remove a monster; never the border walls, never a monster within ``MONSTER_CLEARANCE``
of the avatar (the generator puts monsters far from it). ``edit`` keeps only edits after which
the key and the door are still reachable (``checks.playability_problems``) and the level stays
within ``BOUNDS``, the generator's range over d in [0, 1]: at most as many monsters as it places
at d = 1, at most as many inner walls as its maze keeps at d = 1 (the most: it opens the fewest
walls there), one key and one door (the editor only moves them)."""

from __future__ import annotations

import numpy as np

from gvgai_pcg.games.editing import (
    CountBound,
    EditKind,
    Grid,
    apply_edit,
    choose,
    far_from,
    inner_box,
    move,
    parameter_range,
    place,
)
from gvgai_pcg.games.zelda.generator import HEIGHT, WIDTH, parameters
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


def maze_inner_walls(width: int = WIDTH, height: int = HEIGHT) -> int:
    """Inner walls of the generator's perfect maze before it opens any: the grid inside the border
    less the maze's cells and the passages of its spanning tree (cells - 1)."""
    cells = (width // 2) * (height // 2)
    return (width - 2) * (height - 2) - (2 * cells - 1)


def generator_bounds() -> tuple[CountBound, ...]:
    """What the generator can place, from its own ``parameters``: (walls opened, monsters)."""
    fewest_opened, most_opened = parameter_range(parameters, 0)
    _, most_monsters = parameter_range(parameters, 1)
    walls = maze_inner_walls()
    return (
        CountBound("monsters", MONSTERS, 0, most_monsters),
        CountBound("inner walls", "w", max(walls - most_opened, 0), walls - fewest_opened, inner=True),
        CountBound("keys", "+", 1, 1),
        CountBound("doors", "g", 1, 1),
    )


BOUNDS = generator_bounds()

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
    return apply_edit(level, seed, KINDS, "zelda", BOUNDS)[1]
