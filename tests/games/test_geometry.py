"""Cell look-ups shared by the games."""

import torch

from gvgai_pcg.games.geometry import any_last, count_last, grid_hits


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
    from gvgai_pcg.games.geometry import pick

    table = torch.tensor([5, -1, 7])
    codes = torch.tensor([[2, 0], [1, 1]])
    assert torch.equal(pick(table, codes), table[codes])
