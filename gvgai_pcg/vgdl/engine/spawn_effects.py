"""spawn and spawnIfHasMore: each application makes a sprite of ``stype`` where the first is.

Java draws a double at every application of both (RULES.md §1.5); only a ``spawn`` with ``prob``
below 1 can fail, so only that one draws here. Its draw is keyed ``(seed, tick, rank, stream)``:
``stream`` is the first's group's (``layout``), ``rank`` the sprite's place in the order Java's
drawing rules visit its group (kinds by their first drawing rule, then slot order; a kind no such
rule names after them). A first that meets several seconds would draw once each in Java: a
``spawn`` with ``prob`` below 1 refuses that at run time instead of drawing once for all.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.games import rng
from gvgai_pcg.games.geometry import CELL, aligned_cell, covered_cells
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.columns import resource_column
from gvgai_pcg.vgdl.engine.creation import create
from gvgai_pcg.vgdl.engine.frame import Frame, Side
from gvgai_pcg.vgdl.layout import GRID, RECORD

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

ONE_DRAW = "a spawn with prob below 1 whose first overlaps several seconds (one draw each) is not implemented"


def applications(frame: Frame, rule: Rule, first: Side) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """Positions ``[B, N]`` of the firsts of ``first`` and how many seconds each eligible one
    overlaps (the rule's applications to it). A grid's firsts are its cells (``N = H * W``, row-major),
    each applied to as often as its sprites not yet killed times the seconds covering it."""
    if first.representation == GRID:
        return cell_applications(frame, rule, first)
    x, y = frame.xy(first)
    hits = frame.overlap_count(x, y, first.aligned, first, list(rule.seconds)) * frame.eligible(first)
    return x, y, hits


def cell_applications(
    frame: Frame, rule: Rule, first: Side
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """``applications`` of a grid type's sprites: each cell's position and its sprites not yet
    killed times the seconds that cover the cell."""
    standing, touched = standing_and_touched(frame, rule, first)
    batch, height, width = frame.grid(first.key).shape
    cells = torch.arange(height * width, device=standing.device)
    x = (CELL * (cells % width)).expand(batch, -1)
    y = (CELL * (cells // width)).expand(batch, -1)
    return x, y, standing * touched


def standing_and_touched(frame: Frame, rule: Rule, first: Side) -> tuple[torch.Tensor, torch.Tensor]:
    """Per cell ``[B, H * W]`` of grid type ``first``: its sprites that may still be a first (not
    killed, the rule not shielded) and how many of the rule's seconds (records or tables, killed
    ones included) cover the cell."""
    grid = frame.grid(first.key)
    batch, height, width = grid.shape
    touched = torch.zeros(batch, height * width, dtype=torch.int64, device=grid.device)
    for second in rule.seconds:
        x, y = frame.xy(second)
        index, valid = (aligned_cell if second.aligned else covered_cells)(x, y, height, width)
        valid = valid & frame.present(second).unsqueeze(-1)
        touched = touched.scatter_add(1, index.reshape(batch, -1), valid.reshape(batch, -1).long())
    standing = (grid - frame.grid_killed(first.key)).reshape(batch, -1).long()
    if frame.skip is not None:
        standing = standing * ~frame.skip.unsqueeze(-1)
    return standing, touched


def spawn(frame: Frame, rule: Rule) -> None:
    made = str(rule.plan.values["stype"])
    prob = float(rule.plan.values["prob"])
    for first in rule.firsts:
        x, y, hits = applications(frame, rule, first)
        frame.add_score(rule.score * hits.sum(-1))  # Java scores a failed draw too
        if prob < 1:
            assert_async((hits <= 1).all(), ONE_DRAW)
            hits = hits * (draw(frame, rule, first) < prob)
        create(frame, made, hits, x, y, rule.overflow)


def spawn_if_has_more(frame: Frame, rule: Rule) -> None:
    """Fires where the first holds at least ``limit`` of ``resource`` (``spend`` is 0: checks)."""
    made = str(rule.plan.values["stype"])
    column = resource_column(str(rule.plan.values["resource"]))
    limit = int(rule.plan.values["limit"])
    for first in rule.firsts:
        x, y, hits = applications(frame, rule, first)
        held = frame.entry(first.key).get(column)
        held = held.unsqueeze(-1) if first.representation == RECORD else held
        fired = hits * (held >= limit)
        frame.add_score(rule.score * fired.sum(-1))
        create(frame, made, fired, x, y, rule.overflow)


def draw(frame: Frame, rule: Rule, first: Side) -> torch.Tensor:
    """U[0, 1) ``[B, K]`` for the sprites of ``first``'s table (see the module docstring)."""
    layout = frame.layout
    group = layout.group(first.key)
    drawing = [
        index
        for index, plan in enumerate(layout.plan.pairs)
        if plan.name == "spawn" and float(plan.values["prob"]) < 1
    ]
    order = tuple(
        next((index for index in drawing if name in layout.plan.pairs[index].firsts), len(layout.plan.pairs))
        for name in group.kinds
    )
    table = frame.entry(first.key)
    alive, kind = table.get("alive"), table.get("kind")
    # every drawing rule of the group draws the same numbers while its sprites stay: drawn once
    known = frame.draws.get(first.key)
    if known is not None and known[0] is alive and known[1] is kind and not torch.compiler.is_compiling():
        return known[2]
    position = lookup(order, kind)  # [B, K]
    slots = torch.arange(kind.shape[1], device=kind.device)
    before = (position.unsqueeze(-1) < position.unsqueeze(-2)) | (
        (position.unsqueeze(-1) == position.unsqueeze(-2)) & (slots.unsqueeze(-1) < slots.unsqueeze(-2))
    )  # [B, j, k]: sprite j is visited before sprite k
    rank = (before & alive.unsqueeze(-1)).sum(-2)
    drawn = rng.uniform(frame.value("seed"), frame.value("tick"), rank, group.stream)
    frame.draws[first.key] = (alive, kind, drawn)  # holds alive, kind: their ids stay theirs
    return drawn
