"""One registry of curricula: training (its configs) and the Gymnasium API accept the same
names and build the same level source and shared state from them."""

from __future__ import annotations

import pytest
import yaml

from gvgai_pcg.config import REGIMENS as CONFIG_REGIMENS
from gvgai_pcg.config import config_dir
from gvgai_pcg.curricula import registered_curricula
from gvgai_pcg.envs.level_sources import (
    FixedLevel,
    GeneratedLevels,
    GeneratedLevelSet,
    RandomDifficultyLevels,
    UniformLevels,
)
from gvgai_pcg.gym.adapter import GVGAIGymEnv
from gvgai_pcg.gym.regimens import regimen_kind, regimen_names
from gvgai_pcg.rl.environment import curriculum_run, training_source


def test_the_config_group_the_schema_and_the_table_name_the_same_regimens():
    files = {yaml.safe_load(path.read_text())["name"] for path in (config_dir() / "regimen").glob("*.yaml")}
    assert files == set(CONFIG_REGIMENS) == set(registered_curricula()) == set(regimen_names())
    assert {"pcg", "ppcg", "dr"} <= set(regimen_names(generated=True))
    assert {"lv", "lv0-3", "human", "levels"} <= set(regimen_names(generated=False))


@pytest.mark.parametrize("make", [regimen_kind, lambda name: GVGAIGymEnv("zelda", regimen=name)])
def test_an_unknown_regimen_is_refused_with_every_valid_name(make):
    with pytest.raises(ValueError, match="unknown regimen 'pcg2'") as error:
        make("pcg2")
    assert all(name in str(error.value) for name in regimen_names())


@pytest.mark.parametrize(
    ("overrides", "gym_kwargs", "source_type"),
    [
        (["regimen=lv", "regimen.level=2"], {"regimen": "lv", "level": 2}, FixedLevel),
        (["regimen=lv0-3"], {"regimen": "lv0-3"}, UniformLevels),
        (["regimen=human"], {"regimen": "human"}, UniformLevels),
        (["regimen=pcg", "regimen.difficulty=0.5"], {"regimen": "pcg", "difficulty": 0.5}, GeneratedLevels),
        (
            ["regimen=pcg", "regimen.difficulty=0.5", "regimen.num_levels=3"],
            {"regimen": "pcg", "difficulty": 0.5, "num_levels": 3},
            GeneratedLevelSet,
        ),
        (["regimen=ppcg"], {"regimen": "ppcg"}, GeneratedLevels),
        (["regimen=dr"], {"regimen": "dr"}, RandomDifficultyLevels),
    ],
)
def test_training_and_gymnasium_build_the_same_source_and_curriculum(
    make_config, overrides, gym_kwargs, source_type
):
    cfg = make_config(["game=zelda", *overrides])
    trained = training_source("zelda", cfg.regimen)
    gym = GVGAIGymEnv("zelda", **gym_kwargs).regimen
    assert type(trained) is type(gym.source.source) is source_type
    assert vars(trained) == vars(gym.source.source)  # the same levels, set, seeds and difficulty
    curriculum, gym_curriculum = curriculum_run(cfg.regimen, "zelda").state, gym.curriculum
    assert (curriculum is None) == (gym_curriculum is None) == (cfg.regimen.name not in ("pcg", "ppcg"))
    if curriculum is not None:
        assert (curriculum.mode, curriculum.difficulty, curriculum.alpha) == (
            gym_curriculum.mode,
            gym_curriculum.difficulty,
            gym_curriculum.alpha,
        )
