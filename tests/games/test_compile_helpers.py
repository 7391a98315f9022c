"""The compile helpers read levels as the plain per-character definition says."""

import pytest
import torch

from gvgai_pcg.games.base import char_entities, char_grid, pad_level
from gvgai_pcg.games.geometry import CELL
from gvgai_pcg.levels import Level, human_levels


def reference_entities(levels, kinds, capacity=None):
    """One slot per sprite, in (kind code, row, column) order, written one at a time."""
    found = [
        sorted((kinds[ch], r, c) for r, row in enumerate(lv.rows) for c, ch in enumerate(row) if ch in kinds)
        for lv in levels
    ]
    size = max([len(f) for f in found] + [capacity or 0])
    x, y, kind = (torch.zeros(len(levels), size, dtype=torch.int64) for _ in range(3))
    alive = torch.zeros(len(levels), size, dtype=torch.bool)
    for b, sprites in enumerate(found):
        for k, (code, r, c) in enumerate(sprites):
            x[b, k], y[b, k], kind[b, k], alive[b, k] = CELL * c, CELL * r, code, True
    return x, y, kind, alive


def padded_human_levels(game: str) -> list[Level]:
    levels = human_levels(game)
    height, width = max(lv.height for lv in levels), max(lv.width for lv in levels)
    return [pad_level(lv, height, width) for lv in levels]


@pytest.mark.parametrize("game", ["zelda", "solarfox", "frogs", "boulderdash"])
@pytest.mark.parametrize("capacity", [None, 200])
def test_entities_follow_kind_then_row_major_order(game, capacity):
    levels = padded_human_levels(game)
    present = sorted({ch for lv in levels for row in lv.rows for ch in row})
    kinds = {ch: (3 * i) % 4 for i, ch in enumerate(present[::2])}  # several chars per kind code
    table = char_entities(levels, kinds, torch.device("cpu"), capacity=capacity)
    x, y, kind, alive = reference_entities(levels, kinds, capacity)
    assert table.batch_size == alive.shape
    for name, expected in (("x", x), ("y", y), ("kind", kind), ("alive", alive)):
        assert torch.equal(table.get(name), expected), name


def test_no_sprite_gives_an_empty_table():
    level = Level("zelda", ("www", "wAw", "www"))
    table = char_entities([level, level], {"g": 0}, torch.device("cpu"))
    assert table.batch_size == (2, 0)


def test_grids_mark_every_listed_character():
    levels = padded_human_levels("frogs")
    grid = char_grid(levels, "w0", torch.device("cpu"))
    expected = torch.tensor([[[ch in "w0" for ch in row] for row in lv.rows] for lv in levels])
    assert torch.equal(grid, expected)


def test_levels_of_different_sizes_share_the_largest_grid_with_nothing_outside_their_screens():
    grid = char_grid([Level("zelda", ("www",)), Level("zelda", ("ww", "wA"))], "w", torch.device("cpu"))
    assert grid.tolist() == [
        [[True, True, True], [False, False, False]],
        [[True, True, False], [True, False, False]],
    ]


def test_characters_of_no_legend_are_ignored():
    level = Level("zelda", ("w\u00e9\u20acw", "wA.w"))  # two characters beyond ASCII, one beyond 255
    assert char_grid([level], "w", torch.device("cpu")).sum() == 4
    assert char_entities([level], {"\u00e9": 0}, torch.device("cpu")).get("x").tolist() == [[10]]
