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
