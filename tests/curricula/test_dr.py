"""DR: a new generated level every episode at d ~ U[0, 1], per env and episode, reproducible from
the episode seed, reported by the env as ``level_difficulty``."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.config import compose_config
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.level_sources import RandomDifficultyLevels, uniform_difficulties
from gvgai_pcg.generators import generate_level
from gvgai_pcg.rl.environment import EnvFactory, curriculum_run, training_levels, training_source


def test_its_difficulties_are_uniform_and_a_function_of_the_episode_seed():
    seeds = torch.arange(20_000, dtype=torch.int64) * 7919 + 3
    drawn = uniform_difficulties(seeds)
    assert torch.equal(drawn, uniform_difficulties(seeds.clone()))
    assert float(drawn.min()) >= 0.0 and float(drawn.max()) < 1.0
    counts = torch.histc(drawn, bins=10, min=0.0, max=1.0)
    assert (counts - 2000).abs().max() < 200  # about 4.5 standard deviations of a bin
    assert abs(float(torch.corrcoef(torch.stack([drawn, (seeds % 2**31).double()]))[0, 1])) < 0.05


def test_each_level_is_generated_at_its_drawn_difficulty():
    source = RandomDifficultyLevels("frogs")
    seeds = torch.tensor([5, 2**40 + 9, 77], dtype=torch.int64)
    levels = source.next_levels(torch.arange(3), seeds, torch.zeros(3, dtype=torch.float64))
    drawn = source.level_difficulties(torch.arange(3), seeds, torch.zeros(3, dtype=torch.float64))
    assert len(set(drawn.tolist())) == 3
    for level, d, seed in zip(levels, drawn.tolist(), seeds.tolist(), strict=True):
        assert level == generate_level("frogs", d, seed % 2**31) and level.seed == seed % 2**31


def test_regimen_dr_trains_on_it_with_no_shared_state():
    cfg = compose_config(["game=frogs", "regimen=dr"])
    assert cfg.run_name == "frogs-dr-tiles-compact-seed0"
    assert isinstance(training_source("frogs", cfg.regimen), RandomDifficultyLevels)
    assert (
        curriculum_run(cfg.regimen, "frogs").state is None and training_levels("frogs", cfg.regimen) is None
    )
    assert source_flags(training_source("frogs", cfg.regimen)) == (True, False)


def source_flags(source) -> tuple[bool, bool]:
    return source.prepare_ahead, source.depends_on_difficulty


@pytest.fixture
def eager(monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")


def test_the_env_reports_each_level_and_replays_it_from_its_seed(eager):
    cfg = compose_config(["game=frogs", "regimen=dr"])
    runs = []
    for _ in range(2):
        env = EnvFactory("frogs", cfg.regimen, 3, "tiles", 4, "cpu", seed=11)()
        out = env.reset()
        seen = [(out["level_seed"].flatten().tolist(), out["level_difficulty"].flatten().tolist())]
        for _ in range(9):  # episodes of at most 4 steps: two or more new levels per env
            out = env.step_and_maybe_reset(out.set("action", torch.zeros(3, dtype=torch.int64)))[1]
            seen.append((out["level_seed"].flatten().tolist(), out["level_difficulty"].flatten().tolist()))
        for level, seed, d in zip(env.current_levels, *seen[-1], strict=True):
            assert level == generate_level("frogs", d, seed)  # it says what it plays
        runs.append(seen)
        env.close()
    assert runs[0] == runs[1]  # the same env seed plays the same levels
    assert len({d for _, ds in runs[0] for d in ds}) >= 6  # a new d every episode and env


def test_a_generated_level_env_reports_the_difficulty_it_was_made_at(eager):
    env = GVGAIEnv("zelda", 2, RandomDifficultyLevels("zelda"), max_steps=3, seed=1)
    out = env.reset()
    assert out["level_difficulty"].dtype == torch.float64 and out["level_difficulty"].shape == (2, 1)
    assert env.observation_spec["level_difficulty"].is_in(out["level_difficulty"])


def test_a_ppcg_env_reports_the_difficulty_its_levels_were_made_at(eager):
    cfg = compose_config(["game=zelda", "regimen=ppcg", "regimen.start=0.3"])
    run = curriculum_run(cfg.regimen, "zelda")
    state = run.state
    env = EnvFactory("zelda", cfg.regimen, 1, "tiles", 5, "cpu", seed=2, run=run)()
    out = env.reset()
    state.shared_difficulty[0] = 0.9  # d moves while the episode runs: the level's d stays
    out = env.step(out.set("action", torch.zeros(1, dtype=torch.int64)))["next"]
    level = env.base_env.current_levels[0]
    assert out["level_difficulty"].item() == 0.3 and out["difficulty"].item() == 0.9
    assert level == generate_level("zelda", 0.3, out["level_seed"].item())


def test_the_gymnasium_envs_report_the_difficulty_dr_drew_for_each_level(eager):
    import gymnasium as gym

    import gvgai_pcg  # noqa: F401 (registers the ids)

    env = gym.make("gvgai_pcg/Zelda-v0", regimen="dr", max_steps=3)
    seen = [env.reset(seed=seed)[1] for seed in range(3)]
    for info in seen:  # the level is the one generated at the reported difficulty
        assert info["level_seed"] >= 0
    levels = [env.unwrapped.engine.current_levels[0]]
    assert levels[0] == generate_level("zelda", seen[-1]["difficulty"], seen[-1]["level_seed"])
    assert len({info["difficulty"] for info in seen}) == 3 and all(0 < i["difficulty"] < 1 for i in seen)
    vector = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=3, regimen="dr", max_steps=3)
    _, info = vector.reset(seed=0)
    assert info["difficulty"][0] == seen[0]["difficulty"] and len(set(info["difficulty"].tolist())) == 3
    vector.close()


@pytest.mark.parametrize(("argument", "takers"), [("difficulty", "pcg, ppcg"), ("alpha", "ppcg")])
def test_the_gymnasium_envs_refuse_the_arguments_dr_would_ignore(argument, takers):
    from gvgai_pcg.gym.adapter import GVGAIGymEnv
    from gvgai_pcg.gym.vector import GVGAIVectorEnv

    for make in (GVGAIGymEnv, lambda **kw: GVGAIVectorEnv(2, **kw)):
        with pytest.raises(ValueError, match=f"regimen 'dr' takes no {argument}=.*take it: {takers}$"):
            make(game="zelda", regimen="dr", **{argument: 0.5})
