"""``stepBack pixelPerfect=True`` (racebet: a camel that runs into a barrier stops flush against it).

Java (``Effect.calculatePixelPerfect``): a first that moved straight along one axis since its last
position is put flush against the second it overlaps, on the side it came from (moving right:
``x := second.x - 10``); any other first goes back to its last position. Java applies it to each
second the first overlapped when the rule began, in list order, while they still overlap: moving
right, each application puts it left of one of them, and the ones further left still overlap, so
it ends flush against the leftmost (and likewise for the other directions). That holds while the
move still points the same way after each application: it does unless a second overlaps where the
first was (then an application can put it behind its last position), which is refused at run
time.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.games.geometry import CELL, covered_cells, overlaps
from gvgai_pcg.vgdl.engine.frame import Frame, Side
from gvgai_pcg.vgdl.layout import GRID, RECORD

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

BEHIND = "a pixelPerfect stepBack whose first overlaps a second where it started the tick is not implemented"
FAR = 1 << 40


def step_back_pixel_perfect(frame: Frame, rule: Rule) -> None:
    """Each eligible first (a record or a table's sprite) that overlaps a second: flush against the
    nearest second it came from, or back to its last position (see the module docstring)."""
    for first in rule.firsts:
        if first.representation == GRID:  # still: it started where it is
            continue
        entry = frame.entry(first.key)
        x, y = frame.xy(first)
        lastx, lasty = _shaped(entry.get("lastx"), first), _shaped(entry.get("lasty"), first)
        low_x, high_x, low_y, high_y, behind = _extents(frame, rule, first, x, y, lastx, lasty)
        met = frame.eligible(first) & (low_x < FAR)
        dx, dy = x - lastx, y - lasty
        right, left = met & (dx > 0) & (dy == 0), met & (dx < 0) & (dy == 0)
        down, up = met & (dy > 0) & (dx == 0), met & (dy < 0) & (dx == 0)
        assert_async(~(met & behind & (right | left | down | up)).any(), BEHIND)
        straight = right | left | down | up
        new_x = torch.where(right, low_x - CELL, torch.where(left, high_x + CELL, x))
        new_y = torch.where(down, low_y - CELL, torch.where(up, high_y + CELL, y))
        new_x = torch.where(met & ~straight, lastx, new_x)
        new_y = torch.where(met & ~straight, lasty, new_y)
        if first.representation == RECORD:
            new_x, new_y = new_x.squeeze(-1), new_y.squeeze(-1)
        entry.update({"x": new_x, "y": new_y})


def _shaped(values: torch.Tensor, side: Side) -> torch.Tensor:
    return values.unsqueeze(-1) if side.representation == RECORD else values


def _extents(
    frame: Frame,
    rule: Rule,
    first: Side,
    x: torch.Tensor,
    y: torch.Tensor,
    lastx: torch.Tensor,
    lasty: torch.Tensor,
) -> tuple[torch.Tensor, ...]:
    """Per first ``[B, N]``: the least and greatest x and y of the seconds it overlaps (``FAR``,
    ``-FAR`` where none), and whether one of them also overlaps its last position."""
    big = torch.full_like(x, FAR)
    low_x, high_x, low_y, high_y = big, -big, big, -big
    behind = torch.zeros_like(x, dtype=torch.bool)
    for second in rule.seconds:
        if second.representation == GRID:
            grid = frame.grid(second.key)
            batch, height, width = grid.shape
            index, valid = covered_cells(x, y, height, width)
            counts = torch.gather(grid.reshape(batch, -1), 1, index.reshape(batch, -1)).view(index.shape)
            meets = valid & (counts > 0)  # [B, N, 4]
            sx, sy = CELL * (index % width), CELL * (index // width)
        else:
            sx, sy = frame.xy(second)
            sx, sy = sx.unsqueeze(-2), sy.unsqueeze(-2)  # [B, 1, K]
            meets = frame.overlap_matrix(x, y, first.aligned, first, second)  # [B, N, K]
        low_x = torch.minimum(low_x, torch.where(meets, sx, FAR).amin(-1))
        high_x = torch.maximum(high_x, torch.where(meets, sx, -FAR).amax(-1))
        low_y = torch.minimum(low_y, torch.where(meets, sy, FAR).amin(-1))
        high_y = torch.maximum(high_y, torch.where(meets, sy, -FAR).amax(-1))
        was = overlaps(lastx.unsqueeze(-1), lasty.unsqueeze(-1), sx, sy)
        behind = behind | (meets & was).any(-1)
    return low_x, high_x, low_y, high_y, behind
