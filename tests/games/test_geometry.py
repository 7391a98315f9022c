"""Cell look-ups shared by the games."""

import torch

from gvgai_pcg.games.geometry import (
    add_at_,
    add_bytes_at_,
    any_last,
    clear_counted_cells_,
    clear_listed_cells_,
    count_last,
    grid_hits,
)


def test_aligned_look_ups_equal_the_general_ones_for_cell_aligned_rectangles():
    generator = torch.Generator().manual_seed(0)
    grid = torch.rand(6, 5, 7, generator=generator) > 0.5
    x = 10 * torch.randint(-2, 9, (6, 4), generator=generator)  # some off the grid
    y = 10 * torch.randint(-2, 7, (6, 4), generator=generator)
    index, hit = grid_hits(grid, x, y)
    aligned_index, aligned_hit = grid_hits(grid, x, y, aligned=True)
    assert torch.equal(hit.sum(-1), aligned_hit.sum(-1))
    first = index.gather(-1, hit.long().argmax(-1, keepdim=True))  # the one hit cell, if any
    assert torch.equal(torch.where(aligned_hit, aligned_index, -1), torch.where(aligned_hit, first, -1))


def test_byte_reductions_equal_torch_ones():
    mask = torch.rand(3, 4, 9) > 0.7
    assert torch.equal(any_last(mask), mask.any(-1))
    assert torch.equal(any_last(mask[:, ::2, 1:]), mask[:, ::2, 1:].any(-1))
    assert torch.equal(count_last(mask), mask.sum(-1).int())
    assert any_last(torch.zeros(2, 0, dtype=torch.bool)).tolist() == [False, False]


def test_pick_is_a_table_look_up_for_codes_of_any_shape():
    from gvgai_pcg.games.lookup import pick

    table = torch.tensor([5, -1, 7])
    codes = torch.tensor([[2, 0], [1, 1]])
    assert torch.equal(pick(table, codes), table[codes])


def test_aligned_overlap_and_step_back_equal_the_general_ones_for_cell_aligned_sprites():
    from gvgai_pcg.games.geometry import overlaps, overlaps_aligned
    from gvgai_pcg.games.rules import step_back_in_order

    generator = torch.Generator().manual_seed(3)
    # Crowded: 6 sprites on a 3x3 patch, each moved by at most one cell, so many collide.
    x = 10 * torch.randint(0, 3, (400, 6), generator=generator)
    y = 10 * torch.randint(0, 3, (400, 6), generator=generator)
    lastx = x + 10 * torch.randint(-1, 2, (400, 6), generator=generator)
    lasty = y + 10 * torch.randint(-1, 2, (400, 6), generator=generator)
    first, second = (torch.rand(2, 400, 6, generator=generator) > 0.2).unbind()
    pairs = overlaps(x.unsqueeze(-1), y.unsqueeze(-1), x.unsqueeze(-2), y.unsqueeze(-2))
    assert torch.equal(
        overlaps_aligned(x.unsqueeze(-1), y.unsqueeze(-1), x.unsqueeze(-2), y.unsqueeze(-2)), pairs
    )
    general = step_back_in_order(x, y, lastx, lasty, first, second)
    aligned = step_back_in_order(x, y, lastx, lasty, first, second, aligned=True)
    assert torch.equal(general[0], aligned[0]) and torch.equal(general[1], aligned[1])
    assert not torch.equal(general[0], x) or not torch.equal(general[1], y)  # some went back


def test_off_screen_is_not_entirely_inside_each_envs_own_screen():
    from gvgai_pcg.games.geometry import off_screen

    x = torch.tensor([[0, 20, 21, -1], [0, 40, 41, 5]])
    y = torch.tensor([[10, 10, 10, 0], [0, 0, 0, -5]])
    screen_h, screen_w = torch.tensor([[20], [10]]), torch.tensor([[30], [50]])
    assert off_screen(x, y, screen_h, screen_w).tolist() == [
        [False, False, True, True],
        [False, False, True, True],
    ]


def test_screen_cell_looks_up_cells_only_on_each_envs_own_screen():
    from gvgai_pcg.games.geometry import screen_cell

    x = torch.tensor([[0, 20, 30, -10], [20, 20, 10, 10]])
    y = torch.tensor([[10, 10, 10, 0], [0, 10, 20, 0]])
    last_x, last_y = torch.tensor([[20], [40]]), torch.tensor([[10], [0]])  # screens 3x2 and 5x1
    index, on = screen_cell(x, y, last_x, last_y, width=6)
    assert on.tolist() == [[True, True, False, False], [True, False, False, True]]
    assert index[on].tolist() == [6, 8, 2, 1]
    assert ((index >= 0) & (index < 6 * 2)).all()  # clamped onto the screen: never another row's cell


def test_overlaps_any_tests_only_the_selected_sprites_by_rectangles():
    from gvgai_pcg.games.geometry import overlaps_any

    tx, ty = torch.tensor([[0, 30], [0, 0]]), torch.tensor([[25, 0], [0, 0]])
    present = torch.tensor([[True, True], [False, False]])
    x, y = torch.tensor([[0, 0, 9, 21], [0, 0, 0, 0]]), torch.tensor([[16, 35, 30, 5], [0, 0, 0, 0]])
    which = torch.tensor([[True, True, True, False], [True, False, False, False]])
    # (0, 16) and (9, 30) overlap the sprite at (0, 25); (0, 35) only touches it; (21, 5) overlaps
    # the one at (30, 0) but is not selected; env 1's sprites are not present.
    assert overlaps_any(x, y, which, tx, ty, present).tolist() == [[True, False, True, False], [False] * 4]
    assert overlaps_any(x[:, 0], y[:, 0], which[:, 0], tx, ty, present).tolist() == [True, False]


def test_each_cell_of_equals_floor_division_on_its_stated_range():
    from gvgai_pcg.games.geometry import cell_of, centre_cell_of, small_cell_of

    wide = torch.arange(-10000, 33000)
    assert torch.equal(cell_of(wide), torch.div(wide, 10, rounding_mode="floor"))
    screen = torch.arange(0, 1029)
    for dtype in (torch.int32, torch.int64):
        assert torch.equal(small_cell_of(screen.to(dtype)), (screen // 10).to(dtype))
    centred = torch.arange(-1005, 14995)
    expected = torch.div(centred + 5, 10, rounding_mode="floor") + 100
    assert torch.equal(centre_cell_of(centred), expected.to(torch.int32))


def test_flat_and_row_cells_agree_with_the_general_cell_look_up():
    from gvgai_pcg.games.geometry import covered_cells, flat_cell, gather_cells, row_cells

    index, inside = flat_cell(torch.tensor([-1, 0, 6, 7, 3]), torch.tensor([0, 4, 4, 2, 5]), 5, 7)
    assert inside.tolist() == [False, True, True, False, False]
    assert index[inside].tolist() == [28, 34]
    generator = torch.Generator().manual_seed(1)
    x = torch.randint(-15, 80, (6, 3), generator=generator)
    y = 10 * torch.randint(0, 5, (6, 3), generator=generator)  # rows: y a multiple of 10
    cells, valid = row_cells(x, y, 5, 7)
    general, general_valid = covered_cells(x, y, 5, 7)
    assert torch.equal(valid.sum(-1), general_valid.sum(-1))
    assert torch.equal(
        torch.where(valid, cells, -1), torch.where(general_valid[..., :2], general[..., :2], -1)
    )
    grid = torch.rand(6, 5, 7, generator=generator) > 0.5
    assert torch.equal(
        gather_cells(grid, cells, valid),
        grid.view(6, -1).gather(1, cells.view(6, -1)).view(cells.shape) & valid,
    )


def test_clear_listed_cells_clears_a_cell_if_any_listing_says_so():
    flat = torch.tensor([[True, True, True, False], [True, True, True, True]])
    index = torch.tensor([[0, 0, 1, 3], [2, 2, 2, 1]])
    clear = torch.tensor([[False, True, False, True], [False, False, False, True]])
    counted = flat.clone()
    clear_counted_cells_(counted, index, clear)  # the way off the CPU
    clear_listed_cells_(flat, index, clear)
    assert flat.tolist() == [[False, True, True, False], [True, False, True, True]]
    assert torch.equal(counted, flat)


def test_byte_sums_wrap_as_the_byte_scatter_add_does():
    generator = torch.Generator().manual_seed(0)
    table = torch.randint(0, 256, (3, 7), dtype=torch.uint8, generator=generator)
    index = torch.randint(0, 7, (3, 12), generator=generator)  # with repeats
    values = torch.randint(0, 256, (3, 12), dtype=torch.uint8, generator=generator)  # 255 is -1
    expected = table.clone().scatter_add_(1, index, values)
    assert torch.equal(add_bytes_at_(table.clone(), index, values), expected)
    assert torch.equal(add_at_(table.clone(), index, values), expected)
