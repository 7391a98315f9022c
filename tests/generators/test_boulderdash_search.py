"""The boulder check's shortcuts agree with a plain breadth-first search on random caves."""

from __future__ import annotations

from collections import deque

import numpy as np

from gvgai_pcg.games.boulderdash import generator as boulderdash


def naive_connected(open_cells: set[int], width: int, start: int, targets: set[int]) -> bool:
    seen, queue = {start}, deque([start])
    while queue:
        i = queue.popleft()
        for j in (i - 1, i + 1, i - width, i + width):
            if j in open_cells and j not in seen:
                seen.add(j)
                queue.append(j)
    return targets <= seen


def random_cave(seed: int, width: int = 12, height: int = 9) -> np.ndarray:
    rng = np.random.default_rng(seed)
    grid = (rng.random((height, width)) < 0.35).astype(np.int8)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = 1
    return grid


def test_bitset_search_matches_bfs():
    for seed in range(300):
        grid = random_cave(seed)
        width = grid.shape[1]
        open_cells = set(np.flatnonzero(grid.ravel() == 0).tolist())
        if len(open_cells) < 3:
            continue
        start, *targets = sorted(open_cells)[:: max(1, len(open_cells) // 4)]
        passable = boulderdash._bitset(grid.ravel() == 0)
        target_bits = sum(1 << t for t in targets)
        assert boulderdash._reaches_all(passable, width, start, target_bits) == naive_connected(
            open_cells, width, start, set(targets)
        )


def test_local_shortcut_never_hides_a_split():
    """If the ring test says blocking a tile cannot disconnect, no pair of its open neighbours is split."""
    for seed in range(300):
        grid = random_cave(seed)
        width = grid.shape[1]
        open_cells = set(np.flatnonzero(grid.ravel() == 0).tolist())
        passable = boulderdash._bitset(grid.ravel() == 0)
        for i in open_cells:
            if boulderdash._may_disconnect(passable, width, i):
                continue
            neighbours = [j for j in (i - 1, i + 1, i - width, i + width) if j in open_cells]
            for j in neighbours[1:]:
                assert naive_connected(open_cells - {i}, width, neighbours[0], {j})
