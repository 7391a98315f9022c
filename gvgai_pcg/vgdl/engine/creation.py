"""Sprites made during play: into a table (the first free slots, reset to a fresh sprite's
columns) or into a grid (a count more in a cell).

Java appends a new sprite to its type's list. Here it takes the first free slot, so a table's
slot order is its list order only for the sprites a level places; ``checks`` refuses the kernels
that read slot order (a same-table stepBack) on a type that is created. A table that keeps
``born`` (``layout``) holds list order there: a created sprite's is ``(tick + 1) * BORN_TICK`` plus
its rank among the tick's creations into the table (after the earlier ones, in creator order).
"""

from __future__ import annotations

import torch

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.vgdl.engine.cells import aligned_cell
from gvgai_pcg.vgdl.engine.columns import fresh_columns, oriented_table
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import BORN_TICK
from gvgai_pcg.vgdl.layout import GRID, TABLE


def create(
    frame: Frame,
    name: str,
    count: torch.Tensor,
    x: torch.Tensor,
    y: torch.Tensor,
    overflow: str,
    last: tuple[torch.Tensor, torch.Tensor] | None = None,
) -> None:
    """Make ``count`` ``[B, N]`` sprites of type ``name`` at ``x, y`` ``[B, N]`` (the creators in
    their processing order): a count more in a cell of a grid, or the first free slots of a table,
    in that order (``overflow`` is the error where a table has too few). ``last``: the new sprites'
    last positions ``[B, N]`` (a transform copies its first's), else ``x, y``."""
    place = frame.layout.places[name]
    if place.representation == GRID:
        grid = frame.grid(name)
        batch, height, width = grid.shape
        index, valid = aligned_cell(x, y, height, width)
        added = torch.zeros(batch, height * width, dtype=grid.dtype, device=grid.device)
        added = added.scatter_add(
            1, index.reshape(batch, -1), (count.unsqueeze(-1) * valid).reshape(batch, -1).to(grid.dtype)
        )
        frame.put(name, grid + added.view(grid.shape))
        return
    if place.representation != TABLE:  # checks refuses creations into a record by these effects
        raise AssertionError(f"{name}: a creation into a {place.representation}")
    frame.make_room(place.key, count)
    table = frame.entry(place.key)
    alive = table.get("alive")
    free = ~alive
    free_rank = free.long().cumsum(-1) - 1  # [B, K]
    end = count.long().cumsum(-1)  # creator n makes the sprites end[n - 1] .. end[n] - 1
    assert_async((end[:, -1] <= free.sum(-1)).all(), overflow)
    # the k-th sprite made takes the k-th free slot: its creator is the first n with end[n] > k
    made = free & (free_rank < end[:, -1:])
    creator = torch.searchsorted(end, free_rank.clamp(min=0), right=True).clamp(max=end.shape[-1] - 1)
    new_x, new_y = torch.gather(x, 1, creator), torch.gather(y, 1, creator)
    last_x, last_y = (new_x, new_y) if last is None else (torch.gather(v, 1, creator) for v in last)
    group = frame.layout.group(place.key)
    values = {
        "x": torch.where(made, new_x, table.get("x")),
        "y": torch.where(made, new_y, table.get("y")),
        "lastx": torch.where(made, last_x, table.get("lastx")),
        "lasty": torch.where(made, last_y, table.get("lasty")),
        "kind": torch.where(made, place.kind, table.get("kind")),
        "alive": alive | made,
    }
    if "born" in table.values:
        tick = frame.value("tick").unsqueeze(-1)
        born = table.get("born")
        earlier = (alive & (born >= (tick + 1) * BORN_TICK)).sum(-1, keepdim=True)
        values["born"] = torch.where(made, (tick + 1) * BORN_TICK + earlier + free_rank, born)
    if oriented_table(frame.layout.plan, group.kinds):
        values["ori"] = torch.where(made, frame.layout.orientation[name], table.get("ori"))
    for column, value in fresh_columns(frame.layout.plan, group.kinds).items():
        current = table.get(column)
        values[column] = torch.where(made, torch.full_like(current, value), current)
    table.update(values)
