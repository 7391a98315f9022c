"""How the avatar classes read an action (RULES.md §1.7, §1.8, §2)."""

import torch

from gvgai_pcg.games import get_game
from gvgai_pcg.games.actions import (
    MOVE_ACTIONS,
    SHOOT_ACTIONS,
    USE,
    move_direction,
    move_displacement,
    shoot_avatar,
    shoot_direction,
)
from gvgai_pcg.games.geometry import DOWN, LEFT, NONE, RIGHT, UP


def test_each_game_uses_its_avatar_class_action_set():
    assert get_game("zelda").actions == get_game("boulderdash").actions == SHOOT_ACTIONS
    assert get_game("frogs").actions == get_game("solarfox").actions == MOVE_ACTIONS


def test_actions_map_to_direction_codes():
    shoot = torch.arange(len(SHOOT_ACTIONS))
    assert shoot_direction(shoot).tolist() == [NONE, NONE, LEFT, RIGHT, DOWN, UP]
    move = torch.arange(len(MOVE_ACTIONS))
    assert move_direction(move).tolist() == [NONE, LEFT, RIGHT, DOWN, UP]
    dx, dy = move_displacement(move, 10, torch.int32)
    assert dx.tolist() == [0, -10, 10, 0, 0] and dy.tolist() == [0, 0, 0, 10, -10]
    assert dx.dtype == torch.int32


def test_shoot_avatar_turns_moves_places_and_does_nothing_when_disabled():
    action = torch.tensor([SHOOT_ACTIONS.index("UP"), SHOOT_ACTIONS.index("RIGHT"), USE, USE, USE])
    alive = torch.tensor([True, True, True, True, False])
    ori = torch.full((5,), RIGHT)
    can_place = torch.tensor([True, True, True, False, True])
    x, y = torch.full((5,), 50), torch.full((5,), 30)
    moved = shoot_avatar(action, alive, ori, x, y, can_place)
    assert moved.x.tolist() == [50, 60, 50, 50, 50] and moved.y.tolist() == [30] * 5
    assert moved.ori.tolist() == [UP, RIGHT, RIGHT, RIGHT, RIGHT]  # a new direction only turns it
    assert moved.place.tolist() == [False, False, True, False, False]
    assert (moved.place_x[2].item(), moved.place_y[2].item()) == (60, 30)  # the faced cell
