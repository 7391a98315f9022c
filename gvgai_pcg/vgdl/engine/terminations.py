"""Terminations, checked after cleanup in declaration order: the first that holds ends the game.

Java's ``Timeout`` holds once the game tick (0 on the reset tick) reaches ``limit``; like the
others it is checked in declaration order, so one declared before it that holds in the same tick
decides the game."""

from __future__ import annotations

import torch

from gvgai_pcg.vgdl.engine.frame import Frame, sides
from gvgai_pcg.vgdl.engine.off_grid import off_key
from gvgai_pcg.vgdl.layout import GRID


def check_terminations(frame: Frame) -> None:
    """SpriteCounter: the sprites of its type (and subtypes) still there, disabled avatars not
    counted (cleanup removed them), are at most ``limit``; Timeout: the tick is at least ``limit``."""
    won, lost = frame.value("won"), frame.value("lost")
    decided = torch.zeros_like(won)
    for termination in frame.layout.plan.terminations:
        if termination.java_class == "Timeout":
            ends = (frame.value("tick") >= termination.limit) & ~decided
            won, lost, decided = _decide(termination.win, ends, won, lost, decided)
            continue
        count = torch.zeros_like(frame.value("score"))
        for leaves in termination.counted:
            for side in sides(frame.layout, leaves):
                if side.representation == GRID:
                    count = count + frame.grid(side.key).flatten(1).sum(-1, dtype=torch.int32)
                    if side.key in frame.layout.spills:  # its sprites off the array
                        count = count + frame.entry(off_key(side.key)).get("alive").sum(-1)
                else:
                    count = count + frame.present(side).sum(-1)
        if termination.java_class == "MultiSpriteCounter":  # Java tests equality here
            ends = (count == termination.limit) & ~decided
        else:
            ends = (count <= termination.limit) & ~decided
        won, lost, decided = _decide(termination.win, ends, won, lost, decided)
    frame.put("won", won)
    frame.put("lost", lost)


def _decide(
    win: bool, ends: torch.Tensor, won: torch.Tensor, lost: torch.Tensor, decided: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """``won``, ``lost`` and ``decided`` once a termination ending the games ``ends`` has held."""
    if win:
        won = won | ends
    else:
        lost = lost | ends
    return won, lost, decided | ends
