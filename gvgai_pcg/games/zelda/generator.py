"""Zelda generator (GENERATORS.md §1.2, v3): a perfect maze opened up by d, then avatar, door, key
and enemies placed by distance.

The level is always the full 13x9. Walls removed ``Nw = floor(96 o)`` with openness
``o = 0.3(1-d) + 0.1 + 0.1r``; enemies ``Ne = floor(5.85 e)`` with ``e = 0.4d + 0.2r``; the door and
key prefer tiles far from the avatar, weighted by ``k = 1 + 0.7d + 0.3r``.

Noisy sorts: the original orders candidates with an asymmetric random comparator
(``dist(A,b) - k dist(A,a) + 9(2r-1)``) whose result depends on the JS engine's sort. We use the
noisy-key form GENERATORS.md allows: each candidate gets the key ``-k dist(A,a) + NOISE * (2r-1)``
and the smallest key wins. ``NOISE = 9/sqrt(2)`` gives the difference of two keys the same noise
variance as one comparator call (U(-9, 9)). This keeps the documented intent (door and key
further away as d grows); a comparison sort with the inconsistent comparator does not, see
docs/generators.md. Connectivity holds by construction: a perfect maze with walls only removed.
"""

from __future__ import annotations

import math

import numpy as np

from gvgai_pcg.generators._common import UniformStream, generated_level
from gvgai_pcg.levels.level import Level

WIDTH, HEIGHT = 13, 9
NOISE = 9 / math.sqrt(2)  # half-width of the per-candidate key noise; see the module docstring
_DIRECTIONS = ((-1, 0), (0, -1), (0, 1), (1, 0))
_ENEMIES = "123"


def parameters(difficulty: float, r: UniformStream) -> tuple[int, int, float]:
    """(walls to remove, enemies, distance factor k) from d, in the original's draw order."""
    d = difficulty
    openness = (1 - d) * 0.3 + 0.1 * r() + 0.1
    enemy_fraction = d * 0.4 + 0.2 * r()
    distance = d * 0.7 + 0.3 * r()
    walls = math.floor(openness * (WIDTH - 1) * (HEIGHT - 1))
    enemies = math.floor(enemy_fraction * 0.05 * WIDTH * HEIGHT)
    return walls, enemies, distance + 1


def perfect_maze(cells_x: int, cells_y: int, r: UniformStream) -> np.ndarray:
    """Randomised Prim maze rendered as a (2 cells_y + 1, 2 cells_x + 1) grid, 1 = wall."""
    grid = np.ones((2 * cells_y + 1, 2 * cells_x + 1), dtype=np.int8)
    visited = [[False] * cells_x for _ in range(cells_y)]
    frontier = [(math.floor(r() * cells_x), math.floor(r() * cells_y))]
    while frontier:
        i = math.floor(r() * len(frontier))
        x, y = frontier[i]
        frontier[i] = frontier[-1]
        frontier.pop()
        if visited[y][x]:
            continue
        neighbours = []
        for dx, dy in _DIRECTIONS:
            nx, ny = x + dx, y + dy
            if 0 <= nx < cells_x and 0 <= ny < cells_y:
                if visited[ny][nx]:
                    neighbours.append((dx, dy))
                frontier.append((nx, ny))
        if neighbours:
            dx, dy = neighbours[math.floor(r() * len(neighbours))]
            grid[2 * y + 1 + dy, 2 * x + 1 + dx] = 0
        visited[y][x] = True
        grid[2 * y + 1, 2 * x + 1] = 0
    return grid


def separator_walls(grid: np.ndarray) -> np.ndarray:
    """(row, col) of interior walls whose two vertical or two horizontal neighbours are open."""
    inner = grid[1:-1, 1:-1] == 1
    vertical = (grid[:-2, 1:-1] == 0) & (grid[2:, 1:-1] == 0)
    horizontal = (grid[1:-1, :-2] == 0) & (grid[1:-1, 2:] == 0)
    return np.argwhere(inner & (vertical | horizontal)) + 1


def _noisy_first(score: np.ndarray, rng: np.random.Generator, count: int = 1) -> np.ndarray:
    """Indices of the ``count`` smallest ``score + NOISE * U(-1, 1)``, smallest first."""
    keys = score + NOISE * (2 * rng.random(score.shape[0]) - 1)
    return np.argsort(keys, kind="stable")[:count]


def generate(difficulty: float, seed: int) -> Level:
    """A 13x9 Zelda level at ``difficulty``; the same seed gives the same level."""
    rng = np.random.default_rng(seed)
    r = UniformStream(rng)
    walls_to_remove, enemies, k = parameters(difficulty, r)
    grid = perfect_maze(WIDTH // 2, HEIGHT // 2, r)
    walls = separator_walls(grid)
    opened = walls[rng.permutation(len(walls))[:walls_to_remove]]
    grid[opened[:, 0], opened[:, 1]] = 0

    tiles = np.argwhere(grid == 0)[rng.permutation(int((grid == 0).sum()))]
    avatar, tiles = tiles[0], tiles[1:]
    to_avatar = np.abs(tiles - avatar).sum(axis=1)
    door_index = _noisy_first(-k * to_avatar, rng)[0]
    door = tiles[door_index]
    keep = np.ones(len(tiles), dtype=bool)
    keep[door_index] = False
    tiles, to_avatar = tiles[keep], to_avatar[keep]
    to_door = np.abs(tiles - door).sum(axis=1)
    key_index = _noisy_first(-k * to_avatar - to_door, rng)[0]
    key = tiles[key_index]
    keep = np.ones(len(tiles), dtype=bool)
    keep[key_index] = False
    tiles, to_avatar = tiles[keep], to_avatar[keep]
    enemy_tiles = tiles[_noisy_first(-to_avatar.astype(float), rng, enemies)]

    chars = np.where(grid == 1, "w", ".").astype("<U1")
    chars[tuple(avatar)] = "A"
    chars[tuple(door)] = "g"
    chars[tuple(key)] = "+"
    for row, col in enemy_tiles:
        chars[row, col] = _ENEMIES[math.floor(r() * 3)]
    return generated_level("zelda", ["".join(row) for row in chars.tolist()], difficulty, seed)
