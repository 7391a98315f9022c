"""``transformTo`` from table sprites into a grid type (Boulderdash: a butterfly a crab meets
becomes a diamond): the new sprite is one more in the count of the first's cell.

The first (a table's sprite or a record) is on whole cells (``checks``), so its cell is one grid
cell, as long as it is on the grid's array; off it, a table sprite's new sprite goes to the grid
type's table of sprites off the array, in the first's slot (``off_grid``), and a record's is
refused at run time (camelRace's avatar becomes a ``winnerPlayer`` where it stands). A grid type's
sprites become ``stype`` sprites in their own cells (zenpuzzle: the ground the avatar walks on
turns into ``walked``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.vgdl.engine.cells import aligned_cell
from gvgai_pcg.vgdl.engine.frame import Frame, Side
from gvgai_pcg.vgdl.engine.off_grid import off_key, put_off_grid
from gvgai_pcg.vgdl.engine.spawn_effects import standing_and_touched
from gvgai_pcg.vgdl.layout import GRID, RECORD

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

OFF_SCREEN = "transformTo into a still (grid) type from a record off the screen is not implemented"


def transform_into_grid(frame: Frame, rule: Rule) -> None:
    """Each first not yet killed (nor disabled) that overlaps a second: a ``stype`` sprite is added
    where it is and the first is killed (an avatar only disabled: it goes on scoring for every
    second it overlaps); the score changes once for another first, since it is then killed."""
    made = str(rule.plan.values["stype"])
    grid = frame.grid(made)
    batch, height, width = grid.shape
    for first in rule.firsts:
        if first.representation == GRID:
            grid = _cells_into_grid(frame, rule, first, grid)
            continue
        x, y = frame.xy(first)
        hits = frame.overlap_count(x, y, first.aligned, first, list(rule.seconds)) * frame.eligible(first)
        fire = (hits > 0) & ~frame.disabled_mask(first)
        index, inside = aligned_cell(x, y, height, width)
        index, inside = index.squeeze(-1), inside.squeeze(-1)
        if first.representation == RECORD:
            assert_async(~(fire & ~inside).any(), OFF_SCREEN)
        else:
            off = frame.entry(off_key(made))
            off.update(put_off_grid(off.values, fire & ~inside, x, y))
        added = torch.zeros(batch, height * width, dtype=grid.dtype, device=grid.device)
        added = added.scatter_add(1, index, (fire & inside).to(grid.dtype))
        grid = grid + added.view(grid.shape)
        frame.put(made, grid)
        frame.kill(first, fire)
        applied = hits if first.key in frame.layout.avatars else fire.long()
        frame.add_score(rule.score * applied.sum(-1))


def _cells_into_grid(frame: Frame, rule: Rule, first: Side, grid: torch.Tensor) -> torch.Tensor:
    """A grid type's sprites into the grid ``stype`` (``grid``, returned with the new sprites):
    every sprite not yet killed in a cell a second covers is transformed, once (then killed)."""
    standing, touched = standing_and_touched(frame, rule, first)
    fired = torch.where(touched > 0, standing, torch.zeros_like(standing)).view(grid.shape)
    grid = grid + fired.to(grid.dtype)
    frame.put(str(rule.plan.values["stype"]), grid)
    frame.killed[first.key] = frame.grid_killed(first.key) + fired.to(grid.dtype)
    frame.add_score(rule.score * fired.flatten(1).sum(-1))
    return grid
