"""Levels smaller than the game's grid are padded (docs/fidelity.md)."""

import pytest

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games import registered_games
from gvgai_pcg.games.base import pad_level
from gvgai_pcg.levels import Level


def test_pad_level_adds_wall_rows_and_columns():
    padded = pad_level(Level("zelda", ("wAgw",)), 3, 6, "w")
    assert padded.rows == ("wAgwww", "wwwwww", "wwwwww")


@pytest.mark.skipif("frogs" not in registered_games(), reason="Frogs is not registered")
def test_frogs_lvl4_is_padded_with_a_wall_row():
    env = GVGAIEnv("frogs", levels="frogs_lvl4")
    td = env.reset()
    assert td.get("tiles").shape[-2:] == (11, 28)
    assert env.current_levels[0].height == 10  # the level itself is the official 10-row one
    wall = env.game.tile_types.index("wall")
    assert td.get("tiles")[0, wall, 10].all()
