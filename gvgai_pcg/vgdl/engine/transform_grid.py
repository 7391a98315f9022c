"""``transformTo`` from table sprites into a grid type (Boulderdash: a butterfly a crab meets
becomes a diamond): the new sprite is one more in the count of the first's cell.

The first is on whole cells (``checks``), so its cell is one grid cell, as long as it is on the
grid's array; off it, the new sprite goes to the grid type's table of sprites off the array, in
the first's slot (``off_grid``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.vgdl.engine.cells import aligned_cell
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.off_grid import off_key, put_off_grid

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule


def transform_into_grid(frame: Frame, rule: Rule) -> None:
    """Each first not yet killed that overlaps a second: a ``stype`` sprite is added where it is,
    the first is killed and the score changes (once: it is then killed)."""
    made = str(rule.plan.values["stype"])
    grid = frame.grid(made)
    batch, height, width = grid.shape
    for first in rule.firsts:
        x, y = frame.xy(first)
        fire = frame.eligible(first) & (
            frame.overlap_count(x, y, first.aligned, first, list(rule.seconds)) > 0
        )
        index, inside = aligned_cell(x, y, height, width)
        index, inside = index.squeeze(-1), inside.squeeze(-1)
        off = frame.entry(off_key(made))
        off.update(put_off_grid(off.values, fire & ~inside, x, y))
        added = torch.zeros(batch, height * width, dtype=grid.dtype, device=grid.device)
        added = added.scatter_add(1, index, (fire & inside).to(grid.dtype))
        grid = grid + added.view(grid.shape)
        frame.put(made, grid)
        frame.mark_killed(first.key, fire)
        frame.add_score(rule.score * fire.sum(-1))
