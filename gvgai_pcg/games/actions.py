"""How the avatar classes read a Gym action (RULES.md §1.7, §1.8, §2), once for every game.

Two action sets exist: ShootAvatar's (Zelda, Boulderdash) ``NIL, USE, LEFT, RIGHT, DOWN, UP`` and
that of the avatars without USE (MovingAvatar in Frogs, OngoingAvatar in Solarfox) ``NIL, LEFT,
RIGHT, DOWN, UP``. An action becomes a direction code of :mod:`gvgai_pcg.games.geometry`
(``NONE`` for NIL and USE); what a direction then does to the avatar is its class's rule, which
for ShootAvatar two games share (:func:`shoot_avatar`).
"""

from __future__ import annotations

from functools import cache
from typing import NamedTuple

import torch

from gvgai_pcg.games.geometry import (
    CELL,
    DIRECTION_DX,
    DIRECTION_DY,
    DOWN,
    LEFT,
    NONE,
    RIGHT,
    UP,
    direction_dx,
    direction_dy,
)
from gvgai_pcg.games.lookup import lookup

NIL, USE = 0, 1
SHOOT_ACTIONS = ("NIL", "USE", "LEFT", "RIGHT", "DOWN", "UP")
MOVE_ACTIONS = ("NIL", "LEFT", "RIGHT", "DOWN", "UP")
# The direction of each action of MOVE_ACTIONS.
MOVE_DIRECTIONS = (NONE, LEFT, RIGHT, DOWN, UP)


def shoot_direction(action: torch.Tensor) -> torch.Tensor:
    """Direction code of ShootAvatar actions (any shape): NONE for NIL and USE."""
    return torch.where(action >= 2, action - 2, torch.full_like(action, NONE))


def move_direction(action: torch.Tensor) -> torch.Tensor:
    """Direction code of actions of :data:`MOVE_ACTIONS` (any shape): NONE for NIL."""
    return lookup(MOVE_DIRECTIONS, action)


def move_displacement(
    action: torch.Tensor, distance: int, dtype: torch.dtype
) -> tuple[torch.Tensor, torch.Tensor]:
    """The (x, y) displacement, as ``dtype``, of a move of ``distance`` px in the direction of
    actions of :data:`MOVE_ACTIONS` (any shape; NIL stays): one look-up per axis."""
    steps = _move_steps.__wrapped__ if torch.compiler.is_compiling() else _move_steps  # no cache in a graph
    return (
        lookup(steps(DIRECTION_DX, distance), action, dtype),
        lookup(steps(DIRECTION_DY, distance), action, dtype),
    )


@cache
def _move_steps(unit: tuple[int, ...], distance: int) -> tuple[int, ...]:
    return tuple(distance * unit[direction] for direction in MOVE_DIRECTIONS)


class ShootAvatarUpdate(NamedTuple):
    """The result of a ShootAvatar's update (all ``[B]``)."""

    x: torch.Tensor
    y: torch.Tensor
    ori: torch.Tensor
    place: torch.Tensor  # whether it creates its sprite (USE, and ``can_place``)
    place_x: torch.Tensor  # where that sprite goes: the cell it faces, before its move
    place_y: torch.Tensor


def shoot_avatar(
    action: torch.Tensor,
    alive: torch.Tensor,
    ori: torch.Tensor,
    x: torch.Tensor,
    y: torch.Tensor,
    can_place: torch.Tensor,
) -> ShootAvatarUpdate:
    """ShootAvatar (RULES.md §2) for ``[B]`` avatars: a direction other than the one it faces only
    turns it, the faced one moves it 10 px; USE creates its sprite in the faced cell where
    ``can_place`` (a singleton that does not exist yet). A disabled avatar (not ``alive``) does
    nothing."""
    direction = shoot_direction(action)
    pressed = alive & (direction != NONE)
    step = (pressed & (direction == ori)).long() * CELL
    new_ori = torch.where(pressed, direction, ori)
    place = alive & (action == USE) & can_place
    return ShootAvatarUpdate(
        x=x + step * direction_dx(direction),
        y=y + step * direction_dy(direction),
        ori=new_ori,
        place=place,
        place_x=x + CELL * direction_dx(new_ori),
        place_y=y + CELL * direction_dy(new_ori),
    )
