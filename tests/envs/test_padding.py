"""Levels smaller than the game's grid are padded outside their screens (docs/fidelity.md)."""

import json

import pytest
import torch
from tensordict import TensorDict

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games import registered_games
from gvgai_pcg.games.base import OUTSIDE, pad_level, screen_size
from gvgai_pcg.levels import Level
from tests.games.golden_replay import GOLDEN_DIR


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


@pytest.mark.parametrize("name", ["walk_into_boulder", "step_out_into_boulder", "stepback_kill"])
def test_an_open_level_in_the_env_plays_as_the_java_engine(name):
    """The env pads the 2- and 3-cell levels of the off-grid traces to Boulderdash's 26x13 grid;
    its avatar walks below its own screen into the padding and is stepped back (and killed) there
    exactly as in the Java recording, with the trace's score changes as rewards."""
    trace = json.loads((GOLDEN_DIR / f"boulderdash_offgrid_{name}.json").read_text())
    env = GVGAIEnv("boulderdash", levels=Level("boulderdash", tuple(trace["level"])))
    env.reset()
    game, score = env.game, 0
    assert env.state.get("wall").shape[1:] == (13, 26)
    for expected in trace["ticks"][1:]:
        action = torch.tensor([game.actions.index(expected["action"])])
        td = env.step(TensorDict({"action": action}, batch_size=[1]))
        snap = game.snapshot(env.state, 0)
        assert snap == {key: expected[key] for key in snap}, f"tick {expected['tick']}"
        assert td.get(("next", "reward")).item() == expected["score"] - score
        score = expected["score"]
