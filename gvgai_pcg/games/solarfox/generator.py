"""Solarfox generator (GENERATORS.md §1.3, v3): mirrored pill patterns in a 10x11 arena.

d raises the pill target ``P = floor(50.4 p)`` with ``p = 0.8d + 0.1 + 0.1r``, spreads the pills
out (concentration ``c = 0.4d + 0.4 + 0.2r`` shrinks the margins) and moves the two enemies'
start columns towards the centre. Pills are drawn in one half (or quarter) and mirrored, and
duplicate draws overwrite, so the final count is at most P. A quirk kept from the original:
with top-bottom symmetry the middle row (row 5 of 11) is drawable but never mirrored.
No sorting happens here, so no noisy-comparator choice is needed.
"""

from __future__ import annotations

import math

import numpy as np

from gvgai_pcg.generators._common import UniformStream, generated_level
from gvgai_pcg.levels.level import Level

WIDTH, HEIGHT = 10, 11
EMPTY, PILL, POWER_PILL = 0, 1, 2
LEFT_RIGHT, TOP_BOTTOM, BOTH = 0, 1, 2
MAX_ATTEMPTS = 100  # draws of one level; a draw has no pill with probability about 1e-5


def parameters(difficulty: float, r: UniformStream) -> tuple[int, float, int, int]:
    """(pill target P, concentration c, enemy start es, enemy end ee) in the original's draw order."""
    d = difficulty
    pill_fraction = d * 0.8 + 0.1 * r() + 0.1
    concentration = d * 0.4 + 0.2 * r() + 0.4
    enemy_start = (1 - d) * 0.5 + 0.5
    enemy_end = (1 - d) * 0.3 + 0.5
    pills = math.floor(pill_fraction * 0.7 * (WIDTH - 2) * (HEIGHT - 2))
    return (
        pills,
        concentration,
        math.floor(enemy_start * (WIDTH - 2) / 2),
        math.floor(enemy_end * (WIDTH - 2) / 2),
    )


def enemy_offsets(start: int, end: int, r: UniformStream) -> tuple[int, int]:
    """Column offsets of the top and bottom enemy from the centre column."""
    top = math.floor(2 * r()) * math.floor(r() * (start - end) + end)
    if r() < 0.5:
        top = -top
    bottom = math.floor(r() * (start - end) + end)
    if r() < 0.5:
        bottom = -bottom
    if r() < 0.8:
        if r() < 0.8:
            bottom = -top
        else:
            bottom = -abs(bottom) * int(np.sign(top))
    return top, bottom


def _jewel(jewel_type: int, r: UniformStream) -> int:
    if jewel_type == 0 or (jewel_type == 2 and r() < 0.5):
        return PILL
    return POWER_PILL


def place_pills(grid: list[list[int]], pills: int, concentration: float, r: UniformStream) -> None:
    """Draw pills in the first half (or quarter) of the inner rectangle and mirror them."""
    jewel_type = math.floor(r() * 3)
    symmetry = math.floor(r() * 3)
    margin_x = math.floor(WIDTH / 2 - concentration * WIDTH / 2)
    margin_y = math.floor(HEIGHT / 2 - concentration * HEIGHT / 2)
    span_x = WIDTH - 2 - 2 * margin_x
    span_y = HEIGHT - 2 - 2 * margin_y
    half_x = symmetry in (LEFT_RIGHT, BOTH)
    half_y = symmetry in (TOP_BOTTOM, BOTH)
    draws = math.ceil(pills / 4) if symmetry == BOTH else math.ceil(pills / 2)
    for _ in range(draws):
        x = math.floor(r() * span_x / (2 if half_x else 1)) + 1 + margin_x
        y = math.floor(r() * span_y / (2 if half_y else 1)) + 1 + margin_y
        grid[y][x] = _jewel(jewel_type, r)
    if half_x:
        for row in grid:
            for x in range(WIDTH // 2):
                if row[x] != EMPTY:
                    row[WIDTH - x - 1] = row[x]
    if half_y:
        for y in range(HEIGHT // 2):
            for x in range(WIDTH):
                if grid[y][x] != EMPTY:
                    grid[HEIGHT - y - 1][x] = grid[y][x]


def generate(difficulty: float, seed: int) -> Level:
    """A 10x11 Solarfox level at ``difficulty``; the same seed gives the same level.

    The player's tile can erase the only pills (a few seeds in 100,000 at d = 0, where the pills
    crowd the centre), which would leave a level won at its first tick; such a draw is redrawn
    from the seed's next stream (docs/fidelity.md)."""
    for attempt in range(MAX_ATTEMPTS):
        rng = np.random.default_rng(seed if attempt == 0 else [seed, attempt])
        rows = _draw(difficulty, UniformStream(rng))
        if any("b" in row or "p" in row for row in rows):
            return generated_level("solarfox", rows, difficulty, seed)
    raise RuntimeError(f"solarfox: no draw with a pill in {MAX_ATTEMPTS} (d={difficulty}, seed={seed})")


def _draw(difficulty: float, r: UniformStream) -> list[str]:
    """The rows of one draw of the original algorithm."""
    pills, concentration, enemy_start, enemy_end = parameters(difficulty, r)
    grid = [[EMPTY] * WIDTH for _ in range(HEIGHT)]
    player_x = math.floor(WIDTH / 2 + 2 * r() - 1)
    player_y = math.floor(HEIGHT / 2 + 2 * r() - 1)
    top, bottom = enemy_offsets(enemy_start, enemy_end, r)
    place_pills(grid, pills, concentration, r)

    chars = [["." if y in (0, HEIGHT - 1) else "+" for _ in range(WIDTH)] for y in range(HEIGHT)]
    for y, row in enumerate(grid):
        for x, cell in enumerate(row):
            if cell == PILL:
                chars[y][x] = "b"
            elif cell == POWER_PILL:
                chars[y][x] = "p"
    chars[player_y][player_x] = "A"
    chars[0][WIDTH // 2 + top] = "2"
    chars[HEIGHT - 1][WIDTH // 2 + bottom] = "1"
    for row in chars:
        row[0] = row[-1] = "w"
    return ["".join(row) for row in chars]
