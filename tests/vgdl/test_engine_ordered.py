"""The stepBack among one table's sprites for tables on whole cells along one axis
(``engine.ordered``) gives what the pairwise ``step_back_in_order`` gives, gathered to the sprites
near another (eager) and over every slot (as compiled)."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.games.rules import step_back_in_order
from gvgai_pcg.vgdl.engine import ordered


def crowded_columns(seed: int, batch: int = 300, slots: int = 12):
    """Sprites in three columns (x on whole cells) falling 0-3 px, often into each other; some
    absent, some not allowed to move back."""
    generator = torch.Generator().manual_seed(seed)
    x = 10 * torch.randint(0, 3, (batch, slots), generator=generator)
    lasty = torch.randint(-12, 40, (batch, slots), generator=generator)
    y = lasty + torch.randint(0, 4, (batch, slots), generator=generator)
    second = torch.rand(batch, slots, generator=generator) < 0.8
    first = second & (torch.rand(batch, slots, generator=generator) < 0.9)
    return x, y, x.clone(), lasty, first, second


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("axis", ["x", "y"])
def test_ordered_step_back_equals_the_pairwise_one(seed, axis):
    x, y, lastx, lasty, first, second = crowded_columns(seed)
    if axis == "y":  # rows instead of columns
        x, y, lastx, lasty = y, x, lasty, lastx
    expected = step_back_in_order(x, y, lastx, lasty, first, second, aligned=False)
    assert not torch.equal(expected[0] + expected[1], x + y)  # some went back
    actual = ordered.ordered_step_back(x, y, lastx, lasty, first, second, axis == "x")
    assert torch.equal(actual[0], expected[0]) and torch.equal(actual[1], expected[1])
    major, minor = (x, y) if axis == "x" else (y, x)
    last_major, last_minor = (lastx, lasty) if axis == "x" else (lasty, lastx)
    back = ordered._resolve(
        major * ordered.KEY_AXIS + minor, last_major * ordered.KEY_AXIS + last_minor, first, second
    )
    assert torch.equal(torch.where(back, lastx, x), expected[0])
    assert torch.equal(torch.where(back, lasty, y), expected[1])


@pytest.mark.slow  # a compile of its own (about 10 CPU-seconds)
def test_ordered_step_back_compiled_equals_the_pairwise_one():
    compiled = torch.compile(ordered.ordered_step_back, fullgraph=True, dynamic=False)
    x, y, lastx, lasty, first, second = crowded_columns(0, batch=50)
    expected = step_back_in_order(x, y, lastx, lasty, first, second, aligned=False)
    actual = compiled(x, y, lastx, lasty, first, second, True)
    assert torch.equal(actual[0], expected[0]) and torch.equal(actual[1], expected[1])
