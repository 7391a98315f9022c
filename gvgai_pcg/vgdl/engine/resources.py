"""The resource effects: ``collectResource`` (a Resource sprite is taken by the record it
touches), ``killIfOtherHasMore`` (a sprite goes when the record it touches holds enough) and
``changeResource`` (the first's count grows, within the resource type's ``limit``).

Java keeps a record's resources in a map; here each is a field ``resource_<type>`` of the record
(``columns.held_resources``; ``changeResource``'s first holds a column per resource it changes,
a record or a table). The firsts of the first two are grid types and the seconds records
(killIfOtherHasMore: or tables) on whole cells (``checks``), so the sprites a second touches are
the counts of the one cell it covers.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.games.geometry import aligned_cell
from gvgai_pcg.vgdl.engine.columns import resource_column
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.off_grid import off_key, off_overlaps
from gvgai_pcg.vgdl.engine.spawn_effects import applications
from gvgai_pcg.vgdl.layout import RECORD

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule


def collect_resource(frame: Frame, rule: Rule) -> None:
    """collectResource: each first (a Resource, not yet killed) on the second's cell, in turn,
    while the second holds fewer than the type's ``limit``: the second gets ``min(value, limit -
    held)``, the first is killed, the score changes. Otherwise nothing (score if fired). Off the
    grid's array, the firsts are those a transform left there (``off_grid``), in slot order."""
    (first,) = rule.firsts
    resource = frame.layout.plan.types[first.key].values
    value, limit = int(resource["value"]), int(resource["limit"])
    field = f"resource_{first.key}"
    for second in rule.seconds:
        record = frame.entry(second.key)
        held, alive = record.get(field), record.get("alive")
        x, y = frame.xy(second)
        index, counts = frame.cell_counts(first.key, x, y, True)
        index, counts = index.view(-1, 1), counts.view(-1, 1)
        killed = frame.grid_killed(first.key).flatten(1)
        here = (counts - killed.gather(1, index)).squeeze(-1).long() * alive
        fires = torch.clamp(limit - held + value - 1, min=0) // value  # applications below the limit
        taken = torch.minimum(here, fires)
        frame.killed[first.key] = killed.scatter_add(1, index, taken.unsqueeze(-1).to(killed.dtype)).view(
            frame.grid(first.key).shape
        )
        if first.key in frame.layout.spills:
            key = off_key(first.key)
            meets = off_overlaps(frame.entry(key).values, frame.killed.get(key), x, y, True).squeeze(1)
            meets = meets & alive.unsqueeze(-1)
            more = torch.minimum(meets.sum(-1), fires - taken)
            frame.mark_killed(key, meets & (meets.cumsum(-1) <= more.unsqueeze(-1)))
            taken = taken + more
        record.set(field, held + torch.minimum(taken * value, torch.clamp(limit - held, min=0)))
        frame.add_score(rule.score * taken)


def kill_if_other_has_more(frame: Frame, rule: Rule) -> None:
    """killIfOtherHasMore: every first not yet killed in the cell of a second (a record or a
    table's sprite, killed ones included) holding at least ``limit`` of ``resource`` is killed
    (score if fired): once, however many such seconds it meets."""
    (first,) = rule.firsts
    resource, limit = str(rule.plan.values["resource"]), int(rule.plan.values["limit"])
    grid = frame.grid(first.key)
    batch, height, width = grid.shape
    covered = torch.zeros(batch, height * width, dtype=torch.int64, device=grid.device)
    for second in rule.seconds:
        held = frame.entry(second.key).get(resource_column(resource))
        held = held.unsqueeze(-1) if second.representation == RECORD else held
        rich = frame.present(second) & (held >= limit)
        x, y = frame.xy(second)
        index, inside = aligned_cell(x, y, height, width)
        covered = covered.scatter_add(
            1, index.reshape(batch, -1), (rich.unsqueeze(-1) & inside).reshape(batch, -1).long()
        )
    killed = frame.grid_killed(first.key)
    newly = torch.where(covered.view(grid.shape) > 0, grid - killed, torch.zeros_like(grid))
    frame.killed[first.key] = killed + newly
    frame.add_score(rule.score * newly.flatten(1).sum(-1, dtype=torch.int64))


def change_resource(frame: Frame, rule: Rule) -> None:
    """changeResource: ``value`` is positive (``checks``); of ``n`` applications the first
    ``(limit - held) // value`` fire (Java's ``getResourceLimit``), each scoring."""
    resource = str(rule.plan.values["resource"])
    value = int(rule.plan.values["value"])
    limit = int(frame.layout.plan.types[resource].values["limit"])
    column = resource_column(resource)
    for first in rule.firsts:
        _, _, hits = applications(frame, rule, first)
        entry = frame.entry(first.key)
        held = entry.get(column)
        if first.representation == RECORD:
            hits = hits.squeeze(-1)
        fired = torch.minimum(hits, ((limit - held) // value).clamp(min=0))
        entry.set(column, held + value * fired)
        frame.add_score(rule.score * fired.reshape(fired.shape[0], -1).sum(-1))
