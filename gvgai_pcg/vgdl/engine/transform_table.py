"""``transformTo`` into a type held in a table (camelRace: a camel that reaches the goal becomes a
``winnerNPC`` where it is; racebet: a camel becomes its singleton ``win`` sprite).

Java (``TransformTo``): a first not disabled that overlaps a second gets a new ``stype`` sprite at
its position with its last position copied, and is killed (an avatar that becomes a sprite that is
not an avatar is only disabled, so it goes on colliding and scoring); the score changes at every
application. Where the new type or an ancestor is a singleton (``TypePlan.singleton_guard``) and a
sprite of it exists, killed this tick included, Java makes nothing and kills nothing: the first
stays, and every second it overlaps scores. So in each env only the first firing sprite in
processing order (the rule's kinds in ``iSubTypes`` order, then list order) can make one.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.vgdl.engine.creation import create
from gvgai_pcg.vgdl.engine.frame import Frame, Side, sides
from gvgai_pcg.vgdl.engine.off_grid import off_key
from gvgai_pcg.vgdl.layout import GRID, RECORD

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

# A processing-order key: the kind's rank in the rule, then the sprite's list order.
KIND_RANK = 1 << 40


def transform_into_table(frame: Frame, rule: Rule) -> None:
    """Each eligible first that overlaps a second becomes a ``stype`` sprite of a table (see the
    module docstring). Every first's overlaps are found before anything is made: Java's rule takes
    its firsts and seconds before it applies, so what it makes is neither (infection: a host that
    becomes ``infected`` infects no other host in the same rule)."""
    made = str(rule.plan.values["stype"])
    guard = frame.layout.plan.types[made].singleton_guard
    found = []
    for first in rule.firsts:
        x, y = frame.xy(first)
        hits = frame.overlap_count(x, y, first.aligned, first, list(rule.seconds)) * frame.eligible(first)
        found.append((first, x, y, hits, (hits > 0) & ~frame.disabled_mask(first)))
    taken = exists(frame, guard) if guard else None
    for first, x, y, hits, fire in found:
        if taken is not None:
            fire = _first_in_order(fire, _order(frame, first)) & ~taken.unsqueeze(-1)
            taken = taken | fire.any(-1)
        kept_going = (first.key in frame.layout.avatars) | ~fire  # applied to every second it meets
        frame.add_score(rule.score * torch.where(kept_going, hits, fire.long()).sum(-1))
        create(frame, made, fire.long(), x, y, rule.overflow, last=_last(frame, first))
        frame.kill(first, fire)


def exists(frame: Frame, names: tuple[str, ...]) -> torch.Tensor:
    """``[B]`` bool: a sprite of one of ``names`` is in the game (Java's lists: killed this tick
    included, until cleanup)."""
    count = torch.zeros_like(frame.value("score"))
    for side in sides(frame.layout, names):
        if side.representation == GRID:
            count = count + frame.grid(side.key).flatten(1).sum(-1, dtype=torch.int64)
            if side.key in frame.layout.spills:
                count = count + frame.entry(off_key(side.key)).get("alive").sum(-1)
        else:
            count = count + frame.present(side).sum(-1)
    return count > 0


def _last(frame: Frame, first: Side) -> tuple[torch.Tensor, torch.Tensor]:
    entry = frame.entry(first.key)
    lastx, lasty = entry.get("lastx"), entry.get("lasty")
    if first.representation == RECORD:
        return lastx.unsqueeze(-1), lasty.unsqueeze(-1)
    return lastx, lasty


def _order(frame: Frame, first: Side) -> torch.Tensor:
    """``[B, N]``: the firsts' processing order in the rule, ascending."""
    if first.representation == RECORD:
        return torch.zeros_like(frame.entry(first.key).get("x")).unsqueeze(-1)
    table = frame.entry(first.key)
    kind = table.get("kind")
    rank = torch.zeros_like(kind)
    for position, code in enumerate(first.kinds):
        rank = torch.where(kind == code, position, rank)
    listed = table.get("born") if "born" in table.values else torch.arange(kind.shape[1], device=kind.device)
    return rank * KIND_RANK + listed


def _first_in_order(mask: torch.Tensor, order: torch.Tensor) -> torch.Tensor:
    """``mask`` kept at its first sprite in ``order`` only, per env."""
    keyed = torch.where(mask, order, torch.iinfo(torch.int64).max)
    return mask & (keyed == keyed.amin(-1, keepdim=True))
