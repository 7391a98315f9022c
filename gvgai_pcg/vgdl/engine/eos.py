"""The EOS rules (CORPUS.md, "Java's tick"; RULES.md §1.3-4b): after the timed effects and before
the collision pairs, each sprite of an EOS rule's type (and subtypes) that is at the edge of its
env's screen (not entirely inside it, RULES.md §1.1) and neither killed nor disabled this tick
gets the effect, each rule in Java's order (``plan.eos``), its score added per application.

Every kernel touches only the sprite it is applied to, so one masked operation per rule and side
gives Java's sprite-by-sprite result. Grid types never move: a level's sprites start inside its
screen, so a still sprite is never at the edge.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import torch

from gvgai_pcg.games.geometry import CELL, direction_dx, direction_dy, off_screen
from gvgai_pcg.vgdl.engine.checks import score_of
from gvgai_pcg.vgdl.engine.frame import Frame, Side, sides
from gvgai_pcg.vgdl.engine.layout import Layout
from gvgai_pcg.vgdl.engine.missiles import shared_direction
from gvgai_pcg.vgdl.layout import GRID, RECORD, TABLE
from gvgai_pcg.vgdl.plan import RulePlan


@dataclass(frozen=True)
class EdgeRule:
    plan: RulePlan
    firsts: tuple[Side, ...]  # grid sides left out: never at the edge
    score: int


def make_edge_rules(layout: Layout) -> tuple[EdgeRule, ...]:
    return tuple(
        EdgeRule(
            rule,
            tuple(side for side in sides(layout, rule.firsts) if side.representation != GRID),
            score_of(layout.plan, rule),
        )
        for rule in layout.plan.eos
    )


def apply_edge_rules(frame: Frame, rules: tuple[EdgeRule, ...]) -> None:
    if not rules:
        return
    height, width = CELL * frame.value("height"), CELL * frame.value("width")
    for rule in rules:
        for side in rule.firsts:
            x, y = frame.xy(side)
            screen_h, screen_w = height.unsqueeze(-1), width.unsqueeze(-1)
            edge = off_screen(x, y, screen_h, screen_w) & frame.eligible(side)
            if side.key in frame.disabled:
                edge = edge & ~frame.disabled[side.key].unsqueeze(-1)
            EDGE_KERNELS[rule.plan.name](frame, side, edge, screen_h, screen_w)
            if rule.score:
                frame.add_score(rule.score * edge.sum(-1))


def _write_xy(frame: Frame, side: Side, x: torch.Tensor, y: torch.Tensor) -> None:
    if side.representation == RECORD:
        x, y = x.squeeze(-1), y.squeeze(-1)
    frame.entry(side.key).update({"x": x, "y": y})


def _field(frame: Frame, side: Side, name: str) -> torch.Tensor:
    value = frame.entry(side.key).get(name)
    return value.unsqueeze(-1) if side.representation == RECORD else value


def edge_step_back(frame: Frame, side: Side, edge: torch.Tensor, *_: torch.Tensor) -> None:
    """stepBack: back to where it started the tick."""
    x, y = frame.xy(side)
    lastx, lasty = _field(frame, side, "lastx"), _field(frame, side, "lasty")
    _write_xy(frame, side, torch.where(edge, lastx, x), torch.where(edge, lasty, y))


def edge_kill(frame: Frame, side: Side, edge: torch.Tensor, *_: torch.Tensor) -> None:
    """killSprite: killed (an avatar disabled)."""
    frame.kill(side, edge)


def edge_wrap(
    frame: Frame, side: Side, edge: torch.Tensor, screen_h: torch.Tensor, screen_w: torch.Tensor
) -> None:
    """wrapAround (offset 0): by its orientation's x if that is not 0, else its y: moving right
    (down) to x = 0 (y = 0), left (up) to the screen's last cell, ``width - 10`` (``height - 10``).
    Java's ``lastmove := 0`` is not held: ``checks`` refuses it for a cooldown above 1 (with a
    cooldown of 1 the gate is open again at its next update)."""
    x, y = frame.xy(side)
    names = frame.layout.group(side.key).kinds if side.representation == TABLE else ()
    shared = shared_direction(frame.layout, tuple(names[code] for code in side.kinds)) if names else None
    if shared is not None and shared[0] != 0:  # one horizontal direction: a number
        far_x = (screen_w - CELL).to(x.dtype).expand_as(x)
        _write_xy(frame, side, torch.where(edge, 0 if shared[0] > 0 else far_x, x), y)
        return
    ori = _field(frame, side, "ori")
    dx, dy = direction_dx(ori), direction_dy(ori)
    far_x, far_y = (screen_w - CELL).to(x.dtype), (screen_h - CELL).to(y.dtype)
    new_x = torch.where(dx > 0, torch.zeros_like(x), torch.where(dx < 0, far_x.expand_as(x), x))
    new_y = torch.where(
        dx != 0, y, torch.where(dy > 0, torch.zeros_like(y), torch.where(dy < 0, far_y.expand_as(y), y))
    )
    _write_xy(frame, side, torch.where(edge, new_x, x), torch.where(edge, new_y, y))


EDGE_KERNELS: dict[str, Callable[..., None]] = {
    "stepBack": edge_step_back,
    "killSprite": edge_kill,
    "wrapAround": edge_wrap,
}
