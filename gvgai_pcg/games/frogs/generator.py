"""Frogs generator (GENERATORS.md §1.4, v3): lanes of grass, street and water between a goal row and
a start row, growing with d and centred in a `w` frame of 28x11.

d widens the map (``W = max(floor(17d + 3r) + 6, 6) + 2``), adds rows (``H = max(floor(2d + 3r) + 4,
4)`` map rows plus a wall line above and below) and shifts lane weights from grass
(``1 - d``) to street (``(1 + 0.5r)d``) and water (``(2 + r)d``). Quirks of the original kept because
they shape the distribution:

* the water run length reuses the street maximum ``M = floor((0.3 + 0.5d + 0.2r) 0.8 H)`` (the
  separate water draw is made and discarded);
* a run of length L >= 2 types only L - 1 rows and leaves the next row grass, so multi-row lanes
  are always followed by a safe row;
* the segment routine stops the whole lane at the first tile index reaching W - 1.

No sorting happens here, so no noisy-comparator choice is needed.
"""

from __future__ import annotations

import math

import numpy as np

from gvgai_pcg.games.frogs import LEVEL_FORMAT as FULL
from gvgai_pcg.generators._common import UniformStream, frame, generated_level
from gvgai_pcg.levels.level import Level

GRASS, STREET, WATER = 0, 1, 2
_VEHICLES = {0: "l_", 1: "x-"}  # per lane direction: (fast, slow)
LONGEST_SEGMENT = 4  # a segment (vehicle or log run) is 1 to this many tiles long


def parameters(difficulty: float, r: UniformStream) -> tuple[int, int, float, float, int]:
    """(width W, map rows H, P(street), P(water), max run M) in the original's draw order."""
    d = difficulty
    width = math.floor((FULL.width - 11) * d + 3 * r()) + 6
    height = math.floor((FULL.height - 9) * d + 3 * r()) + 4
    street = (1 + 0.5 * r()) * d
    water = (2 + r()) * d
    safe = 1 - d
    max_run = 0.3 + 0.5 * d + 0.2 * r()
    r()  # the original draws a water run parameter and never uses it
    total = street + water + safe
    run = math.floor(max_run * 0.8 * height)
    return max(width, 6) + 2, max(height, 4), street / total, water / total, run


def lane_types(height: int, p_street: float, p_water: float, max_run: int, r: UniformStream) -> list[int]:
    """Type of every map row, following the original loop (and its skipped row after runs)."""
    types = [GRASS] * height
    i = 1
    while i < height - 1:
        kind, length = GRASS, 1
        value = r()
        if value < p_street:
            kind, length = STREET, math.floor(r() * max_run) + 1
        elif value < p_street + p_water:
            kind, length = WATER, math.floor(r() * max_run) + 1
        for j in range(length):
            if i >= height - 1:
                break
            types[i] = kind
            if j > 0:
                i += 1
        i += 1
    return types


def segments(width: int, count: int, r: UniformStream) -> list[bool]:
    """Which columns hold a segment tile (vehicle or log); stops at the first index >= W - 1."""
    filled = [False] * width
    start = math.floor(r() * (width / count)) + 1
    for _ in range(count):
        length = math.floor(r() * LONGEST_SEGMENT) + 1
        done = False
        for column in range(start, start + length):
            if column >= width - 1:
                done = True
                break
            filled[column] = True
        start += 2 * length + 1 + math.floor(r() * (width / count))
        if done:
            break
    return filled


def _lane(kind: int, width: int, r: UniformStream) -> list[str]:
    """The characters of one lane row; per-tile speed/spawner draws follow the lane layout."""
    state = math.floor(r() * 2)
    if kind == GRASS:
        return ["w"] + ["+"] * (width - 2) + ["w"]
    if kind == STREET:
        filled = segments(width, math.floor(r() * 0.4 * width) + 2, r)
        fast, slow = _VEHICLES[state]
        return [(fast if r() < 0.5 else slow) if f else "." for f in filled]
    filled = segments(width, math.floor(r() * 0.2 * width) + 1, r)
    row = ["=" if f else "0" for f in filled]
    row[width - 2] = "=" if state == 0 else "spawner"
    row[width - 1] = "spawner"
    return [("3" if r() < 0.5 else "1") if c == "spawner" else c for c in row]


def generate(difficulty: float, seed: int) -> Level:
    """A Frogs level at ``difficulty``, framed to 28x11; the same seed gives the same level."""
    r = UniformStream(np.random.default_rng(seed))
    width, height, p_street, p_water, max_run = parameters(difficulty, r)
    types = lane_types(height, p_street, p_water, max_run, r)
    goal = math.floor(r() * (width - 2)) + 1
    goal_row = ["+"] * width
    goal_row[0] = goal_row[-1] = goal_row[goal - 1] = goal_row[goal + 1] = "w"
    goal_row[goal] = "g"
    avatar = math.floor(r() * (width - 2)) + 1
    start_row = ["w"] + ["+"] * (width - 2) + ["w"]
    start_row[avatar] = "A"
    lanes = [_lane(types[i], width, r) for i in range(1, height - 1)]
    wall = "w" * width
    rows = [wall, "".join(goal_row)] + ["".join(lane) for lane in lanes] + ["".join(start_row), wall]
    return generated_level("frogs", frame(rows, "frogs"), difficulty, seed)
