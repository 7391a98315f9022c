"""bounceForward (Java's BounceForward): a second pushes the first it overlaps one step along the
second's own displacement this tick.

Java takes the second's ``lastDirection`` (``rect - lastrect``), normalises it, flips an axis
where it opposes the second's facing, and moves the first through its physics'
``activeMovement`` by ``(int)(speed * 10)`` px, ``speed`` being the second's (where that is 0,
the first's, or 1): ``(int)`` of each normalised component times that. The first's
``lastrect`` stays where its update left it (so an ``undoAll`` or ``stepBack`` later in the tick
puts it back where it started the tick); it faces the push. A second that did not move pushes
nothing.

Implemented (``checks``) for firsts held in tables, of a class that never moves by itself, with
no cooldown, pushed by records (avatars): no first's push changes whether another first meets
its pusher, so the firsts go at once; several seconds push in ``iSubTypes`` order, each only a
first that still overlaps it (Java re-tests the overlap before every application).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.games.geometry import DOWN, LEFT, NONE, RIGHT, UP, direction_dx, direction_dy
from gvgai_pcg.vgdl.engine.frame import Frame

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule

CELL_PX = 10  # learning mode's cell


def push_px(second_speed: float, first_speed: float) -> int:
    """The px a push moves by: Java's ``activeMovement`` speed (the second's; where 0, the
    first's, or 1 when that is not above 0) times the 10-px cell, truncated."""
    speed = second_speed if second_speed != 0 else (first_speed if first_speed > 0 else 1.0)
    return int(speed * CELL_PX)


def bounce_forward(frame: Frame, rule: Rule) -> None:
    layout = frame.layout
    types = layout.plan.types
    for first in rule.firsts:
        table = frame.entry(first.key)
        names = [layout.group(first.key).kinds[code] for code in first.kinds]
        first_speed = float(types[names[0]].values["speed"])
        for second in rule.seconds:
            pusher = frame.entry(second.key)
            px = push_px(float(types[second.key].values["speed"]), first_speed)
            dx, dy = _direction(pusher)
            x, y = table.get("x"), table.get("y")
            meets = frame.overlap_matrix(x, y, first.aligned, first, second).squeeze(-1)
            pushed = meets & frame.eligible(first)
            step_x = (dx * px).trunc().to(x.dtype).unsqueeze(-1)
            step_y = (dy * px).trunc().to(y.dtype).unsqueeze(-1)
            moves = pushed & ((dx != 0) | (dy != 0)).unsqueeze(-1)
            values = {"x": x + step_x * moves, "y": y + step_y * moves}
            if "ori" in table.values:
                values["ori"] = torch.where(moves, _code(dx, dy).unsqueeze(-1), table.get("ori"))
            table.update(values)
            # Java scores each application, a still pusher's included
            frame.add_score(rule.score * pushed.long().sum(-1))


def _direction(pusher) -> tuple[torch.Tensor, torch.Tensor]:
    """The pusher's normalised displacement this tick (``[B]`` float64), an axis flipped where
    it opposes the pusher's facing (Java multiplies the raw components' signs)."""
    raw_x = (pusher.get("x") - pusher.get("lastx")).to(torch.float64)
    raw_y = (pusher.get("y") - pusher.get("lasty")).to(torch.float64)
    norm = torch.sqrt(raw_x * raw_x + raw_y * raw_y)
    safe = torch.where(norm > 0, norm, torch.ones_like(norm))
    dx, dy = raw_x / safe, raw_y / safe  # Vector2d.normalise: a zero vector stays zero
    ori = pusher.get("ori")
    face_x, face_y = direction_dx(ori, torch.float64), direction_dy(ori, torch.float64)
    dx = torch.where(raw_x * face_x < 0, -dx, dx)
    dy = torch.where(raw_y * face_y < 0, -dy, dy)
    return dx, dy


def _code(dx: torch.Tensor, dy: torch.Tensor) -> torch.Tensor:
    """The direction code of a push along one axis (NONE for a diagonal one, which no code
    names; ``checks`` keeps pushes on the axes where the facing is read)."""
    code = torch.full(dx.shape, NONE, dtype=torch.int64, device=dx.device)
    code = torch.where((dx < 0) & (dy == 0), LEFT, code)
    code = torch.where((dx > 0) & (dy == 0), RIGHT, code)
    code = torch.where((dy > 0) & (dx == 0), DOWN, code)
    return torch.where((dy < 0) & (dx == 0), UP, code)
