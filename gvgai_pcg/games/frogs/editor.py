"""Frogs' level editor (ACCEL's mutations): add or remove a log in a water lane, add or remove a
vehicle in a street lane, move the goal along its row.

Lanes keep their kind: a log (=) goes on water (0) in a row of water, and a vehicle on highway (.)
in a row of highway and vehicles only, in the lane's direction (a lane's vehicles all drive one
way in the generator: x and - right, l and _ left; a lane without vehicles takes either). The
spawners (1-4) and the frog on its log (B) are never touched. The goal moves one or two columns,
with its walls (the generator walls it on both sides), and only above a cell the frog can come
from; the move changes four cells at most."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from gvgai_pcg.games.editing import EditKind, Grid, apply_edit, choose, place
from gvgai_pcg.games.frogs.generator import LONGEST_SEGMENT
from gvgai_pcg.levels.level import Level

WATER_ROW = set("0=1234Bw")  # w: the generator's frame beside a lane
STREET_ROW = set(".-x_lw")
VEHICLES = {"right": "x-", "left": "l_"}  # (fast, slow) per direction
GOAL_SHIFTS = (-2, -1, 1, 2)


def _rows(grid: Grid, kinds: set[str]) -> set[int]:
    """The rows made only of ``kinds`` (water lanes, street lanes)."""
    return {r for r, row in enumerate(grid.cells) if set(row) <= kinds}


def add_log(grid: Grid, rng: np.random.Generator) -> bool:
    water = _rows(grid, WATER_ROW)
    return place(grid, rng, "=", on="0", where=lambda cell: cell[0] in water)


def remove_log(grid: Grid, rng: np.random.Generator) -> bool:
    water = _rows(grid, WATER_ROW)
    return place(grid, rng, "0", on="=", where=lambda cell: cell[0] in water)


def add_vehicle(grid: Grid, rng: np.random.Generator) -> bool:
    street = _rows(grid, STREET_ROW)
    cells = grid.find(".", where=lambda cell: cell[0] in street)
    if not cells:
        return False
    cell = cells[int(rng.integers(len(cells)))]
    lane = set(grid.cells[cell[0]])
    kinds = "".join(chars for chars in VEHICLES.values() if lane & set(chars)) or choose_direction(rng)
    grid[cell] = choose(rng, kinds)
    return True


def choose_direction(rng: np.random.Generator) -> str:
    """The vehicles of a direction drawn uniformly, for a lane without any."""
    return VEHICLES["right"] if rng.random() < 0.5 else VEHICLES["left"]


def remove_vehicle(grid: Grid, rng: np.random.Generator) -> bool:
    street = _rows(grid, STREET_ROW)
    return place(grid, rng, ".", on="".join(VEHICLES.values()), where=lambda cell: cell[0] in street)


def move_goal(grid: Grid, rng: np.random.Generator) -> bool:
    """The goal one or two columns left or right, walls beside it; a wall it leaves becomes grass
    unless it ends the row's grass (the row's own end wall)."""
    goals = grid.find("g")
    if len(goals) != 1:
        return False
    row, old = goals[0]
    new = old + GOAL_SHIFTS[int(rng.integers(len(GOAL_SHIFTS)))]
    cells = grid.cells[row]
    if not (0 <= new - 1 and new + 1 < grid.width) or row + 1 >= grid.height:
        return False
    if grid[(row + 1, new)] == "w" or not _inside_grass(cells, old, new):
        return False
    for column in (old - 1, old, old + 1):
        if cells[column] in "wg" and _inner(cells, column, old):
            cells[column] = "+"
    cells[new - 1], cells[new], cells[new + 1] = "w", "g", "w"
    return True


def _inner(cells: list[str], column: int, goal: int) -> bool:
    """Whether the goal's cell or wall at ``column`` has grass beyond it (so it is not an end wall)."""
    if column == goal:
        return True
    beyond = column + (column - goal)
    return 0 <= beyond < len(cells) and cells[beyond] == "+"


def _inside_grass(cells: list[str], old: int, new: int) -> bool:
    """Whether the new goal cell is grass or one of the old goal's inner walls."""
    return cells[new] == "+" or (abs(new - old) == 1 and _inner(cells, new, old))


@cache
def most_segment_tiles(width: int, start: int = 1) -> int:
    """The most tiles the generator's ``segments`` fills in a lane of ``width`` from column
    ``start`` on: a segment of L tiles at s fills s .. s + L - 1 (not past column width - 2) and
    the next one starts at s + 2 L + 1 or later."""
    if start >= width - 1:
        return 0
    return max(
        min(length, width - 1 - start) + most_segment_tiles(width, start + 2 * length + 1)
        for length in range(1, LONGEST_SEGMENT + 1)
    )


@dataclass(frozen=True)
class LaneBound:
    """At most ``most_segment_tiles(lane width) + spare`` cells of ``chars`` in each lane: a row
    made only of ``lane`` characters (its width: the cells that are not the frame's ``w``)."""

    name: str
    chars: str
    lane: frozenset[str]
    spare: int = 0

    def excess(self, level: Level) -> int:
        total = 0
        for row in level.rows:
            if set(row) <= self.lane:
                have = sum(ch in self.chars for ch in row)
                most = most_segment_tiles(sum(ch != "w" for ch in row)) + self.spare
                total += max(have - most, 0)
        return total


BOUNDS = (
    LaneBound("logs per water lane", "=", frozenset(WATER_ROW), spare=1),
    LaneBound("vehicles per street lane", "".join(VEHICLES.values()), frozenset(STREET_ROW)),
)

KINDS: dict[str, EditKind] = {
    "add_log": add_log,
    "remove_log": remove_log,
    "add_vehicle": add_vehicle,
    "remove_vehicle": remove_vehicle,
    "move_goal": move_goal,
}


def edit(level: Level, seed: int) -> Level:
    """``level`` with one of ``KINDS`` applied, drawn by ``seed`` (gvgai_pcg.games.editing)."""
    return apply_edit(level, seed, KINDS, "frogs", BOUNDS)[1]
