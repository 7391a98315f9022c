"""Levels smaller than the game's grid are padded outside their screens (docs/fidelity.md)."""

import pytest

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games import registered_games
from gvgai_pcg.games.base import OUTSIDE, pad_level, screen_size
from gvgai_pcg.levels import Level


def test_pad_level_adds_cells_outside_the_screen_and_keeps_the_screen_size():
    padded = pad_level(Level("zelda", ("wAgw",)), 3, 6)
    assert padded.rows == ("wAgw" + 2 * OUTSIDE, 6 * OUTSIDE, 6 * OUTSIDE)
    assert screen_size(padded) == (1, 4)
    assert screen_size(pad_level(padded, 4, 7)) == (1, 4)


@pytest.mark.skipif("frogs" not in registered_games(), reason="Frogs is not registered")
def test_frogs_lvl4_is_shown_in_the_full_grid_with_nothing_below_its_screen():
    env = GVGAIEnv("frogs", levels="frogs_lvl4")
    td = env.reset()
    assert td.get("tiles").shape[-2:] == (11, 28)
    assert env.current_levels[0].height == 10  # the level itself is the official 10-row one
    assert env.state.get("height").tolist() == [10]  # and so is its screen
    assert not td.get("tiles")[0, :, 10].any()
