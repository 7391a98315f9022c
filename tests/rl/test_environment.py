"""The training env of each regimen: level sets of your own, and finite generated sets."""

from __future__ import annotations

import logging

import pytest
import torch

from gvgai_pcg.envs.level_sources import TRAINING_SEED_SPACE, GeneratedLevelSet
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels import Level
from gvgai_pcg.rl import train
from gvgai_pcg.rl.environment import EnvFactory, training_levels
from gvgai_pcg.rundir.run_log import read_log

TINY = ["env.num_envs=8", "env.max_steps=20", "total_frames=400", "log.every_episodes=8", "log.curve=false"]


def training_env(make_config, overrides: list[str]):
    cfg = make_config(overrides)
    return EnvFactory(cfg.game.name, cfg.regimen, 16, "tiles", 20, "cpu", 0)()


def seeds_played(env, resets: int = 5) -> set[int]:
    seeds = set()
    for _ in range(resets):
        seeds |= set(env.reset()["level_seed"].flatten().tolist())
    return seeds


def test_a_finite_generated_set_plays_only_its_levels(make_config):
    env = training_env(
        make_config,
        ["regimen=pcg", "regimen.difficulty=0.5", "regimen.num_levels=3", "regimen.start_seed=40"],
    )
    assert seeds_played(env) == {40, 41, 42}
    levels = training_levels("zelda", {"name": "pcg", "difficulty": 0.5, "num_levels": 3, "start_seed": 40})
    assert levels == [generate_level("zelda", 0.5, s) for s in (40, 41, 42)]


def test_unlimited_generated_levels_are_new_every_episode(make_config):
    env = training_env(make_config, ["regimen=pcg", "regimen.num_levels=0"])
    assert len(seeds_played(env)) > 50
    assert training_levels("zelda", {"name": "pcg", "difficulty": 1.0, "num_levels": 0}) is None


def test_a_generated_set_is_reproducible_and_refuses_bad_seeds():
    a, b = GeneratedLevelSet("frogs", 0.3, 1000, 7), GeneratedLevelSet("frogs", 0.3, 1000, 7)
    seeds = torch.arange(50, dtype=torch.int64) * 7919
    assert a.next_levels(torch.arange(50), seeds, torch.zeros(50)) == b.next_levels(
        torch.arange(50), seeds, torch.zeros(50)
    )
    assert a.level(999).seed == 1006
    with pytest.raises(ValueError, match=r"must lie in \[0, 2\*\*31\)"):
        GeneratedLevelSet("frogs", 0.3, 2, TRAINING_SEED_SPACE - 1)
    with pytest.raises(ValueError, match="num_levels >= 1"):
        GeneratedLevelSet("frogs", 0.3, 0)


def test_a_level_set_plays_its_files_and_names_an_unwinnable_one(make_config, tmp_path, caplog):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "open.txt").write_text("wwwwww\nwA.+gw\nwwwwww\n")
    (folder / "locked.txt").write_text(
        "wwwwwwww\nwA....gw\nwwwwwwww\n"
    )  # no key (a level no other test warns about)
    (folder / "notes.md").write_text("not a level")
    with caplog.at_level(logging.WARNING, logger="gvgai_pcg.levels.winnable"):
        env = training_env(make_config, ["regimen=levels", f"regimen.path={folder}"])
    assert "training level locked cannot be won (key (+): needs 1, has 0)" in caplog.text
    env.reset()
    assert {level.name for level in env.current_levels} == {"open", "locked"}
    assert [lv.name for lv in training_levels("zelda", {"name": "levels", "path": str(folder)})] == [
        "locked",
        "open",
    ]


@pytest.mark.parametrize(
    "regimen",
    [
        ["regimen=levels", "regimen.path=LEVELS"],
        ["regimen=pcg", "regimen.num_levels=2", "regimen.difficulty=0"],
    ],
    ids=["levels", "pcg-n2"],
)
def test_a_tiny_run_trains_on_a_level_set(make_config, tmp_path, regimen):
    (tmp_path / "zelda_a.txt").write_text(str(Level("zelda", ("wwwwww", "wA.+gw", "wwwwww"))))
    regimen = [part.replace("LEVELS", str(tmp_path / "zelda_a.txt")) for part in regimen]
    cfg = make_config([*regimen, *TINY, f"out_dir={tmp_path}"])
    result = train(cfg, tmp_path / cfg.run_name)
    assert result.frames == 400 and result.model_path.exists()
    assert cfg.run_name in ("zelda-levels-zelda_a-tiles-compact-seed0", "zelda-pcg0-n2-tiles-compact-seed0")
    rows = read_log(result.log_path)
    assert rows and rows[-1]["episodes"] >= 8


def test_a_training_job_too_short_for_compiling_ticks_eagerly(make_config, tmp_path, monkeypatch):
    """Compiling the tick pays back only past COMPILE_PAYS_BACK_STEPS batched steps (issue 38: a
    20k-frame job took 3.2x its eager time): a 400-frame run's envs tick eagerly."""
    import gvgai_pcg.rl.environment as environment
    from gvgai_pcg.engine.step_plan import COMPILE_PAYS_BACK_STEPS, compile_pays_back

    made = []
    real = environment.GVGAIEnv

    def spy(*args, **kwargs):
        env = real(*args, **kwargs)
        made.append(env.step_plan.compiled)
        return env

    monkeypatch.setattr(environment, "GVGAIEnv", spy)
    cfg = make_config(["regimen=lv", *TINY, f"out_dir={tmp_path}"])
    train(cfg, tmp_path / cfg.run_name)
    assert made and not any(made)
    assert compile_pays_back(COMPILE_PAYS_BACK_STEPS, "cpu") and not compile_pays_back(400 // 8, "cpu")
