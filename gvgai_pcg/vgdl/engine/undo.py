"""undoAll (Java's UndoAll): where a first overlaps a second, every sprite of the game goes back to
where it started the tick (``setRect(lastrect)``), the avatar too.

One application restores everything and a second finds nothing left to undo, so the rule is a
per-env global operation: it fires in the envs where any eligible first overlaps a second (no
position changes before it fires, so testing them all at once is Java's first hit). Java's
``lastrect`` is what each sprite's update saved (``preMovement``): the avatar's and the moving
classes' kernels keep it, and ``npcs.saved_entries`` has every other table and record keep it in a
game with an undoAll. Grid types never move, and their ``lastrect`` is where they are. Facing and
cooldowns stay as they are (Java restores only the rectangle).

Implemented (``checks``) without ``notStype`` and without a score; a grid first only of a type
that no rule kills (its cells are read whole).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.vgdl.engine.frame import Frame, Side
from gvgai_pcg.vgdl.engine.off_grid import off_key
from gvgai_pcg.vgdl.layout import GRID

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule


def undo_all(frame: Frame, rule: Rule) -> None:
    fired = _fires(frame, rule)
    spills = {off_key(name) for name in frame.layout.spills}
    for key, entry in frame.entries.items():
        if key in spills:  # a grid type's sprites off the array: still, like the grid
            continue
        x = entry.get("x")
        back = fired if x.dim() == 1 else fired.unsqueeze(-1)
        back = back & entry.get("alive")
        entry.update(
            {
                "x": torch.where(back, entry.get("lastx"), x),
                "y": torch.where(back, entry.get("lasty"), entry.get("y")),
            }
        )


def _fires(frame: Frame, rule: Rule) -> torch.Tensor:
    """``[B]``: envs where an eligible first overlaps a second."""
    fired = torch.zeros_like(frame.value("score"), dtype=torch.bool)
    for first in rule.firsts:
        if first.representation == GRID:
            fired = fired | _grid_first_met(frame, first, rule.seconds)
            continue
        x, y = frame.xy(first)
        hits = frame.overlap_count(x, y, first.aligned, first, list(rule.seconds)) * frame.eligible(first)
        fired = fired | (hits > 0).any(-1)
    return fired


def _grid_first_met(frame: Frame, first: Side, seconds: tuple[Side, ...]) -> torch.Tensor:
    """``[B]``: envs where a present second covers a cell holding a sprite of grid ``first``
    (overlap is symmetric; ``checks`` admits only grid firsts that no rule kills)."""
    met = torch.zeros_like(frame.value("score"), dtype=torch.bool)
    grid = frame.grid(first.key)
    for second in seconds:
        if second.representation == GRID:  # two still types meet where a cell holds both
            other = grid > 1 if second.key == first.key else frame.grid(second.key) > 0
            met = met | ((grid > 0) & other).flatten(1).any(-1)
            continue
        x, y = frame.xy(second)
        counts = frame.cell_counts(first.key, x, y, second.aligned)[1].sum(-1)
        met = met | ((counts > 0) & frame.present(second)).any(-1)
    if frame.skip is not None:
        met = met & ~frame.skip
    return met
