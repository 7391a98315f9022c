"""Boulderdash's level editor (ACCEL's mutations): add or remove a boulder, a gem (diamond), an
inner wall or an enemy, move the exit.

Edits stay inside the cave's outer wall (the generator's frame included) and keep the
generator's distances: a new boulder more than ``BOULDER_CLEARANCE`` cells from the start and the
exit (a boulder above the start could fall on it at the first ticks), a new enemy more than
``ENEMY_START_CLEARANCE`` from the start and ``ENEMY_EXIT_CLEARANCE`` from the exit, the exit at
least ``MIN_EXIT_DISTANCE`` from the start. ``edit`` keeps only edits after which every gem and
the exit are still reachable (``checks.playability_problems``) and at least nine gems are left.

``BOUNDS``, from the generator's own ``parameters`` over d in [0, 1]: gems between its base ten
plus the fewest and the most extra gems it draws, at most as many boulders and enemies as it
places at d = 1, one exit (the editor only moves it). Inner walls are bounded by the level
format only (the cave's box, ``inner_box``) and the reachability check: a cellular-automaton
cave has no constant that limits its walls."""

from __future__ import annotations

import numpy as np

from gvgai_pcg.games.boulderdash.generator import (
    BASE_GEMS,
    BOULDER_CLEARANCE,
    ENEMY_EXIT_CLEARANCE,
    ENEMY_START_CLEARANCE,
    MIN_EXIT_DISTANCE,
    parameters,
)
from gvgai_pcg.games.editing import (
    Cell,
    CountBound,
    EditKind,
    Grid,
    apply_edit,
    choose,
    distance,
    far_from,
    inner_box,
    move,
    parameter_range,
    place,
)
from gvgai_pcg.levels.level import Level

ENEMIES = "bc"


def add_boulder(grid: Grid, rng: np.random.Generator) -> bool:
    away = far_from(grid.find("Ae"), BOULDER_CLEARANCE)
    return place(grid, rng, "o", on=".", where=away)


def remove_boulder(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, ".", on="o")


def add_gem(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, "x", on=".")


def remove_gem(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, ".", on="x")


def add_wall(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, "w", on=".", where=inner_box(grid))


def remove_wall(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, ".", on="w", where=inner_box(grid))


def add_enemy(grid: Grid, rng: np.random.Generator) -> bool:
    starts, exits = grid.find("A"), grid.find("e")
    from_start = far_from(starts, ENEMY_START_CLEARANCE)
    from_exit = far_from(exits, ENEMY_EXIT_CLEARANCE)
    return place(grid, rng, choose(rng, ENEMIES), on=".-", where=lambda c: from_start(c) and from_exit(c))


def remove_enemy(grid: Grid, rng: np.random.Generator) -> bool:
    return place(grid, rng, "-", on=ENEMIES)


def move_exit(grid: Grid, rng: np.random.Generator) -> bool:
    starts = grid.find("A")

    def far(cell: Cell) -> bool:
        return all(distance(cell, start) >= MIN_EXIT_DISTANCE for start in starts)

    return move(grid, rng, "e", on=".", leave=".", where=far)


def generator_bounds() -> tuple[CountBound, ...]:
    """What the generator can place: ``parameters`` gives (..., enemies N, boulders B, extra gems E)."""
    _, most_enemies = parameter_range(parameters, 4)
    _, most_boulders = parameter_range(parameters, 5)
    fewest_extra, most_extra = parameter_range(parameters, 6)
    return (
        CountBound("gems", "x", BASE_GEMS + fewest_extra, BASE_GEMS + most_extra),
        CountBound("boulders", "o", 0, most_boulders),
        CountBound("enemies", ENEMIES, 0, most_enemies),
        CountBound("exits", "e", 1, 1),
    )


BOUNDS = generator_bounds()

KINDS: dict[str, EditKind] = {
    "add_boulder": add_boulder,
    "remove_boulder": remove_boulder,
    "add_gem": add_gem,
    "remove_gem": remove_gem,
    "add_wall": add_wall,
    "remove_wall": remove_wall,
    "add_enemy": add_enemy,
    "remove_enemy": remove_enemy,
    "move_exit": move_exit,
}


def edit(level: Level, seed: int) -> Level:
    """``level`` with one of ``KINDS`` applied, drawn by ``seed`` (gvgai_pcg.games.editing)."""
    return apply_edit(level, seed, KINDS, "boulderdash", BOUNDS)[1]
