"""The avatar's update, first in Java's tick: each avatar record by its class (ShootAvatar,
MovingAvatar).

Only one avatar record is present at a time (a transform replaces one by another); the others
are masked out, so each is updated in turn without a branch.
"""

from __future__ import annotations

import torch

from gvgai_pcg.games.actions import move_displacement, shoot_avatar
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.ongoing import ongoing_avatar

ORIENTED_CREATIONS = frozenset({"OrientedFlicker"})


def update_avatars(frame: Frame, action: torch.Tensor) -> None:
    """ShootAvatar (RULES.md §2): turn, move, or put its ``stype`` (a singleton Flicker, held as a
    record) in the faced cell, which gets the avatar's facing if its class is oriented."""
    layout = frame.layout
    for name in layout.avatars:
        if layout.plan.types[name].java_class == "OngoingAvatar":
            ongoing_avatar(frame, name, action)
            continue
        if layout.plan.types[name].java_class == "MovingAvatar":
            moving_avatar(frame, name, action)
            continue
        avatar = frame.entry(name)
        made = str(layout.plan.types[name].values["stype"])
        shot = frame.entry(made)
        x, y = avatar.get("x"), avatar.get("y")
        moved = shoot_avatar(action, avatar.get("alive"), avatar.get("ori"), x, y, ~shot.get("alive"))
        avatar.update({"lastx": x, "lasty": y, "x": moved.x, "y": moved.y, "ori": moved.ori})
        place = moved.place
        new_x = torch.where(place, moved.place_x, shot.get("x"))
        new_y = torch.where(place, moved.place_y, shot.get("y"))
        values = {
            "x": new_x,
            "y": new_y,
            "lastx": torch.where(place, new_x, shot.get("lastx")),
            "lasty": torch.where(place, new_y, shot.get("lasty")),
            "age": torch.where(place, torch.zeros_like(shot.get("age")), shot.get("age")),
            "alive": shot.get("alive") | place,
        }
        if layout.plan.types[made].java_class in ORIENTED_CREATIONS:
            values["ori"] = torch.where(place, moved.ori, shot.get("ori"))
        else:
            values["ori"] = torch.where(
                place, torch.full_like(shot.get("ori"), layout.orientation[made]), shot.get("ori")
            )
        shot.update(values)


def moving_avatar(frame: Frame, name: str, action: torch.Tensor) -> None:
    """MovingAvatar (RULES.md §2): ``lastrect := rect``, ``lastmove += 1``; a direction action
    moves it ``step`` px (its cooldown gate, Java's at least 1, is open after ``+= 1``), which
    sets ``lastmove := 0``: a pull later this tick then finds its gate shut."""
    avatar = frame.entry(name)
    alive, x, y = avatar.get("alive"), avatar.get("x"), avatar.get("y")
    step = frame.layout.plan.types[name].step_px
    moves = alive & (action != 0)
    dx, dy = move_displacement(torch.where(moves, action, torch.zeros_like(action)), step, x.dtype)
    lastmove = avatar.get("lastmove") + alive
    avatar.update(
        {
            "lastx": x,
            "lasty": y,
            "x": x + dx,
            "y": y + dy,
            "lastmove": torch.where(moves, torch.zeros_like(lastmove), lastmove),
        }
    )
