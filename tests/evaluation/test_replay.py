"""Replays: one frame per step plus the reset frame, written as an animated GIF."""

import pytest
import torch
from PIL import Image

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.replay import record_episode, write_gif
from gvgai_pcg.games import get_game
from gvgai_pcg.levels import Level, human_level


def standing_still(td):
    return torch.zeros(td.batch_size[0], dtype=torch.int64)


def test_gif_has_one_frame_per_step_plus_the_reset(tmp_path):
    episode = record_episode(human_level("zelda", 0), standing_still, max_steps=5)
    assert episode.length == 5 and len(episode.frames) == 6
    path = write_gif(episode, tmp_path / "still.gif", scale=1)
    with Image.open(path) as gif:
        # the avatar never moves: only the caption keeps the GIF writer from merging frames
        assert gif.n_frames == 6


def test_episode_stops_when_the_game_ends(tmp_path):
    # the avatar walks right into the monster of the corridor: the episode ends early
    level = Level.parse("wwwwww\nwA.1gw\nw+...w\nwwwwww", "zelda")
    right = get_game("zelda").actions.index("RIGHT")
    episode = record_episode(level, lambda td: torch.full((1,), right), max_steps=200)
    assert episode.length < 200 and len(episode.frames) == episode.length + 1


def test_replay_command(tiny_run, tmp_path, capsys):
    out = tmp_path / "replay.gif"
    assert (
        main(["replay", str(tiny_run), "--level", "zelda_lvl0", "--out", str(out), "--max-steps", "8"]) == 0
    )
    with Image.open(out) as gif:
        assert gif.n_frames == int(capsys.readouterr().out.split(": ")[1].split()[0])
        assert gif.n_frames <= 9


@pytest.mark.parametrize("option", [["--fps", "0"], ["--fps", "-5"], ["--scale", "0"]])
def test_replay_refuses_a_frame_rate_or_scale_that_is_not_positive(option, tiny_run, tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["replay", str(tiny_run), "--level", "zelda_lvl0", "--out", str(tmp_path / "a.gif"), *option])
    assert "must be above 0" in capsys.readouterr().err
    assert not (tmp_path / "a.gif").exists()
