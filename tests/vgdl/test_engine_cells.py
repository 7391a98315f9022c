"""The generic step's cell of a sprite on whole cells equals ``geometry.aligned_cell``, on the
grid, off it on every side and on the largest grid its exact division holds."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.games import geometry
from gvgai_pcg.vgdl.engine.cells import aligned_cell


@pytest.mark.parametrize(("height", "width"), [(9, 13), (1, 1), (101, 101), (127, 129), (130, 130)])
def test_aligned_cell_equals_the_geometry_one(height, width):
    x = 10 * torch.arange(-3, width + 3).repeat(height + 6)
    y = 10 * torch.arange(-3, height + 3).repeat_interleave(width + 6)
    index, inside = aligned_cell(x, y, height, width)
    expected_index, expected_inside = geometry.aligned_cell(x, y, height, width)
    assert torch.equal(inside, expected_inside) and inside.any() and not inside.all()
    assert torch.equal(index, expected_index)
