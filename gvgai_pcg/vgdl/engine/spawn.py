"""SpawnPoint (RULES.md §2) held as a still grid: every spawner draws ``u ~ U[0, 1)`` at every
update, and at ticks ``tick % cooldown == 0`` (Java's ``start + tick`` with ``start`` = 0, the
first update of a level spawner) with ``u < prob`` it creates one ``stype`` sprite at its own
position, a sprite of a Missile table (``checks`` refuses the rest).

A spawner's draw is keyed by its cell (``layout.SPAWNER_ROW``) on the spawners' stream. A created
sprite takes a free slot (slots hold no order); its ``born`` keeps Java's list order (this
tick's creations after every earlier sprite, in update order, then row-major) and ``fresh`` its
first update, which is this tick's if its group is updated after the spawners.
"""

from __future__ import annotations

import torch

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.games import rng
from gvgai_pcg.games.geometry import CELL
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import BORN_TICK, SPAWNER_ROW


def spawn_point(frame: Frame, name: str) -> None:
    """One update of every spawner of grid type ``name``."""
    layout = frame.layout
    values = layout.plan.types[name].values
    made = str(values["stype"])
    place = layout.places[made]
    grid = frame.grid(name)
    batch, height, width = grid.shape
    cells = torch.arange(height * width, device=grid.device)
    cell_x, cell_y = CELL * (cells % width), CELL * (cells // width)
    tick = frame.value("tick")
    drawn = rng.uniform(frame.value("seed"), tick, cell_y * SPAWNER_ROW + cell_x, layout.spawner_stream)
    cooldown = max(1, int(values["cooldown"]))
    due = (tick % cooldown == 0).unsqueeze(-1)
    fires = (grid.reshape(batch, -1) > 0) & due & (drawn < float(values["prob"]))
    _create_at_cells(frame, place.key, place.kind, layout.orientation[made], fires, width)


def _create_at_cells(frame: Frame, key: str, kind: int, ori: int, fires: torch.Tensor, width: int) -> None:
    """Put a sprite of kind ``kind`` in table ``key`` on each cell where ``fires`` (``[B, H*W]``),
    in free slots."""
    table = frame.entry(key)
    alive = table.get("alive")
    tick = frame.value("tick").unsqueeze(-1)
    free = ~alive
    count = fires.sum(-1, keepdim=True)
    assert_async(  # no host sync: the tick stays one graph
        (count <= free.sum(-1, keepdim=True)).all(),
        f"{frame.layout.plan.path}: a SpawnPoint found the table {key!r} full (its capacity is the plan's)",
    )
    # this tick's creations so far come first in list order
    earlier = (alive & (table.get("born") >= (tick + 1) * BORN_TICK)).sum(-1, keepdim=True)
    cells = fires.shape[1]
    index = torch.arange(cells, device=fires.device)
    firing = torch.sort(torch.where(fires, index, index + cells), dim=-1).values  # firing cells first
    rank = free.cumsum(-1) - 1  # each free slot takes the firing cell of its rank
    takes = free & (rank < count)
    cell = torch.gather(firing, 1, rank.clamp(0, cells - 1)) % cells
    x, y = CELL * (cell % width), CELL * (cell // width)
    table.update(
        {
            "x": torch.where(takes, x, table.get("x")),
            "y": torch.where(takes, y, table.get("y")),
            "lastx": torch.where(takes, x, table.get("lastx")),
            "lasty": torch.where(takes, y, table.get("lasty")),
            "kind": torch.where(takes, kind, table.get("kind")),
            "ori": torch.where(takes, ori, table.get("ori")),
            "fresh": table.get("fresh") | takes,
            "born": torch.where(takes, (tick + 1) * BORN_TICK + earlier + rank, table.get("born")),
            "alive": alive | takes,
        }
    )
