"""killBoth (Java's KillBoth): a first that overlaps a second kills both, ``scoreChange`` each time.

Java applies it to a first's overlapping seconds in list order while the first is not killed:
a sprite kills itself and its first second, once. A killed second stays a second until cleanup,
so several firsts may all kill (and score for) the same one. In a grid second's cell the sprite
killed is the cell's first (``kill_listed_cells``).

A grid first: each of its sprites in a cell some second covers kills itself and the first second
in list order (``iSubTypes`` order of the seconds' sides, then slot order) that covers that
cell. Implemented (``checks``) for pairs of types that share no type (Java's kind ``P``), with
no avatar first (one only disabled goes on killing every second it overlaps).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.vgdl.engine.frame import Frame, Side
from gvgai_pcg.vgdl.layout import GRID

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

FAR_RANK = 1 << 62  # a cell no second covers


def kill_both(frame: Frame, rule: Rule) -> None:
    for first in rule.firsts:
        if first.representation == GRID:
            _grid_first(frame, rule, first)
        else:
            _sprite_first(frame, rule, first)


def _sprite_first(frame: Frame, rule: Rule, first: Side) -> None:
    x, y = frame.xy(first)
    eligible = frame.eligible(first)
    found = torch.zeros_like(eligible)
    chosen_per_side = []
    for second in rule.seconds:
        if second.representation == GRID:
            index, counts = frame.cell_counts(second.key, x, y, first.aligned)
            hit = counts > 0  # [B, N, c]
        else:
            index, hit = None, frame.overlap_matrix(x, y, first.aligned, first, second)  # [B, N, K]
        hit = hit & eligible.unsqueeze(-1)
        chosen = hit & (hit.cumsum(-1) == 1) & ~found.unsqueeze(-1)
        found = found | hit.any(-1)
        chosen_per_side.append((second, chosen, index))
    touched = found & eligible
    frame.kill(first, touched)
    frame.add_score(rule.score * touched.long().sum(-1))
    for second, chosen, index in chosen_per_side:
        if second.representation == GRID:
            batch = chosen.shape[0]
            kill_listed_cells(frame, second.key, index.reshape(batch, -1), chosen.reshape(batch, -1))
        else:
            frame.kill(second, chosen.any(-2))


def _grid_first(frame: Frame, rule: Rule, first: Side) -> None:
    grid = frame.grid(first.key)
    batch, height, width = grid.shape
    cells = height * width
    rank = torch.full((batch, cells), FAR_RANK, dtype=torch.int64, device=grid.device)
    placed = []
    offset = 0
    for second in rule.seconds:
        x, y = frame.xy(second)
        index, valid = frame.cells(x, y, second.aligned, height, width)  # [B, K, c]
        valid = valid & frame.present(second).unsqueeze(-1)
        slots = x.shape[-1]
        order = offset + torch.arange(slots, device=grid.device).view(1, slots, 1).expand(index.shape)
        order = torch.where(valid, order, torch.full_like(order, FAR_RANK))
        rank = rank.scatter_reduce(1, index.reshape(batch, -1), order.reshape(batch, -1), "amin")
        placed.append((second, index, valid, order))
        offset += slots
    killed = frame.grid_killed(first.key)
    live = (grid - killed).reshape(batch, -1)  # eligible first sprites per cell
    struck = (rank < FAR_RANK) & (live > 0)
    if frame.skip is not None:
        struck = struck & ~frame.skip.unsqueeze(-1)
    newly = torch.where(struck, live, torch.zeros_like(live))
    frame.killed[first.key] = killed + newly.view(grid.shape)
    frame.add_score(rule.score * newly.sum(-1, dtype=torch.int64))
    for second, index, valid, order in placed:
        flat = index.reshape(batch, -1)
        mine = valid & (torch.gather(rank, 1, flat).view(index.shape) == order)
        mine = mine & torch.gather(struck, 1, flat).view(index.shape)
        frame.kill(second, mine.any(-1))


def kill_listed_cells(frame: Frame, key: str, index: torch.Tensor, chosen: torch.Tensor) -> None:
    """Kill one sprite of grid ``key`` in each chosen cell (``index``, ``chosen``: ``[B, c]``)
    that has none killed yet."""
    killed = frame.grid_killed(key)
    batch = killed.shape[0]
    flat = killed.reshape(batch, -1)
    add = chosen & (torch.gather(flat, 1, index) == 0)
    frame.killed[key] = flat.scatter_add(1, index, add.to(flat.dtype)).view(killed.shape)
