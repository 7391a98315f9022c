"""SFL: learnability, the buffer's refresh with a policy, the mix of buffer and DR levels, the
buffer in checkpoints, and a tiny run through the training loop's ``between_updates`` hook."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.config import ConfigError, compose_config
from gvgai_pcg.curricula import get_curriculum
from gvgai_pcg.curricula.base import ActingPolicy
from gvgai_pcg.curricula.sfl import LearnabilityBuffer, learnability, top_levels
from gvgai_pcg.envs.level_sources import RandomDifficultyLevels
from gvgai_pcg.generators import generate_level

TINY_POOL = {
    "name": "sfl",
    "replay_probability": 0.5,
    "buffer_size": 3,
    "pool_size": 6,
    "pool_episodes": 2,
    "rollout_steps": 8,
    "refresh_every_frames": 1000,
    "win_rule": "game",
    "tag": "sfl",
}


def random_policy(actions: int = 5) -> ActingPolicy:
    generator = torch.Generator().manual_seed(0)
    return ActingPolicy(lambda td: torch.randint(0, actions, td.batch_size, generator=generator), "tiles")


def test_learnability_is_highest_for_levels_solved_half_the_time():
    wins = torch.tensor([[1, 1, 1, 1], [0, 0, 0, 0], [1, 0, 1, 0], [1, 0, 0, 0]], dtype=torch.bool)
    assert learnability(wins).tolist() == [0.0, 0.0, 0.25, 0.1875]
    assert top_levels(learnability(wins), 2).tolist() == [2, 3]
    assert top_levels(torch.zeros(4, dtype=torch.float64), 2).tolist() == [0, 1]  # ties: earlier first


def test_an_empty_buffer_plays_dr_levels():
    source = get_curriculum("sfl").make_source("zelda", TINY_POOL)
    seeds, envs = torch.arange(10, dtype=torch.int64) * 7919, torch.arange(10)
    d = torch.zeros(10, dtype=torch.float64)
    assert source.next_levels(envs, seeds, d) == RandomDifficultyLevels("zelda").next_levels(envs, seeds, d)


def test_a_full_buffer_is_replayed_with_its_probability():
    buffer = LearnabilityBuffer(3)
    buffer.replace(
        torch.tensor([0.1, 0.2, 0.3], dtype=torch.float64), torch.tensor([11, 12, 13]), torch.ones(3), 0
    )
    source = get_curriculum("sfl").make_source("zelda", TINY_POOL, buffer)
    n = 400
    seeds, envs, d = (
        torch.arange(n, dtype=torch.int64) * 7919 + 1,
        torch.arange(n),
        torch.zeros(n, dtype=torch.float64),
    )
    levels = source.next_levels(envs, seeds, d)
    buffered = {generate_level("zelda", d, s) for d, s in ((0.1, 11), (0.2, 12), (0.3, 13))}
    replayed = sum(level in buffered for level in levels)
    assert 0.4 * n < replayed < 0.6 * n  # replay_probability 0.5
    reported = source.level_difficulties(envs, seeds, d)
    assert all(
        (level in buffered) == (float(x) in (0.1, 0.2, 0.3))
        for level, x in zip(levels, reported, strict=True)
    )
    assert source.next_levels(envs, seeds, d) == levels  # a function of the episode seed and the buffer


def test_a_refresh_plays_the_pool_and_keeps_its_top(monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    buffer = LearnabilityBuffer(3)
    source = get_curriculum("sfl").make_source("zelda", TINY_POOL, buffer)
    assert source.between_updates(random_policy(), frames=40)  # an empty buffer refreshes at once
    assert (buffer.size, int(buffer.refreshes[0]), int(buffer.refreshed_at[0])) == (3, 1, 40)
    assert 0 <= buffer.difficulty <= 1 and (buffer.learnability[:3] <= 0.25).all()
    assert (buffer.learnability[:3].diff() <= 0).all()  # highest first
    assert not source.between_updates(random_policy(), frames=1039)
    assert source.between_updates(random_policy(), frames=1040) and int(buffer.refreshes[0]) == 2


def test_the_buffer_survives_a_checkpoint():
    buffer = LearnabilityBuffer(2)
    buffer.replace(
        torch.tensor([0.4, 0.9], dtype=torch.float64), torch.tensor([5, 6]), torch.tensor([0.25, 0.1875]), 77
    )
    again = LearnabilityBuffer(2)
    again.load_state_dict(buffer.state_dict())
    assert torch.equal(again.seeds, buffer.seeds) and again.size == 2 and int(again.refreshed_at[0]) == 77
    assert again.difficulty == pytest.approx(0.65)


def test_its_config_composes_and_is_checked():
    cfg = compose_config(["game=zelda", "regimen=sfl"])
    assert cfg.regimen.replay_probability == 0.5 and cfg.regimen.buffer_size <= cfg.regimen.pool_size
    assert cfg.run_name.startswith("zelda-sfl-")
    with pytest.raises(ConfigError, match="buffer_size=500 is more than regimen.pool_size=200"):
        compose_config(["game=zelda", "regimen=sfl", "regimen.buffer_size=500"])


def test_it_trains_and_resumes_with_its_buffer(tmp_path, monkeypatch):
    from gvgai_pcg.rl import train
    from gvgai_pcg.rundir.checkpoint import read_file

    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    options = [
        "game=zelda", "env.num_envs=4", "env.max_steps=6", "log.every_episodes=4", "log.curve=false",
        "regimen=sfl", "regimen.pool_size=4", "regimen.buffer_size=2", "regimen.pool_episodes=2",
        "regimen.rollout_steps=5", "regimen.refresh_every_frames=100", f"out_dir={tmp_path}",
    ]  # fmt: skip
    cfg = compose_config([*options, "total_frames=100"])
    first = train(cfg, tmp_path / cfg.run_name)
    saved = read_file(first.checkpoint_path)["curriculum"]
    assert int(saved["filled"][0]) == 2 and int(saved["refreshes"][0]) >= 1
    cfg = compose_config([*options, "total_frames=300"])
    second = train(cfg, tmp_path / cfg.run_name)
    resumed = read_file(second.checkpoint_path)["curriculum"]
    assert int(resumed["refreshes"][0]) > int(saved["refreshes"][0])  # it went on from the saved buffer


def test_a_worker_process_sees_the_buffer_the_trainer_refreshes(tmp_path):
    """Collector workers get a pickled copy of their source; the buffer, shared through files,
    is the trainer's own."""
    import pickle

    buffer = LearnabilityBuffer(2)
    buffer.share_through(tmp_path / "shared")
    worker_copy = pickle.loads(pickle.dumps(get_curriculum("sfl").make_source("zelda", TINY_POOL, buffer)))
    assert worker_copy.state.size == 0
    buffer.replace(torch.tensor([0.3, 0.6], dtype=torch.float64), torch.tensor([21, 22]), torch.ones(2), 5)
    assert worker_copy.state.size == 2 and worker_copy.state.seeds.tolist() == [21, 22]
    n = 64
    seeds, envs, d = (
        torch.arange(n, dtype=torch.int64) + 3,
        torch.arange(n),
        torch.zeros(n, dtype=torch.float64),
    )
    buffered = {generate_level("zelda", 0.3, 21), generate_level("zelda", 0.6, 22)}
    assert any(level in buffered for level in worker_copy.next_levels(envs, seeds, d))
