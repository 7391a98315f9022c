"""reverseDirection: the first's orientation is negated at each application (an odd number of
overlapped seconds reverses it, an even one leaves it)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.games.geometry import DIRECTION_DX
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.spawn_effects import applications

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

# Each direction code's opposite (LEFT, RIGHT, DOWN, UP, NONE).
OPPOSITE = (1, 0, 3, 2, 4)
assert len(OPPOSITE) == len(DIRECTION_DX)


def reverse_direction(frame: Frame, rule: Rule) -> None:
    """Firsts are tables that keep an orientation (``checks``)."""
    for first in rule.firsts:
        _, _, hits = applications(frame, rule, first)
        entry = frame.entry(first.key)
        ori = entry.get("ori")
        entry.set("ori", torch.where(hits % 2 == 1, lookup(OPPOSITE, ori), ori))
