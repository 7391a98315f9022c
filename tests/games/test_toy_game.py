"""A fifth game is its definition plus one registration: the toy game of ``tests/games/toy_game.py``
(rules, generator, level format, one level, all outside the package) registered through the
public API, and a second one through the ``gvgai_pcg.games`` entry-point group, runs through the
TorchRL env, a generator-driven PPCG env, the Gymnasium API and one A2C training batch, with no
change to gvgai_pcg."""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch
from torchrl.envs.utils import check_env_specs

import gvgai_pcg.plugins as plugins_module
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.difficulty import DifficultyTransform
from gvgai_pcg.envs.gym_registration import env_id, register_envs
from gvgai_pcg.envs.level_sources import GeneratedLevels
from gvgai_pcg.envs.reset_rows import RowResetTransformedEnv
from gvgai_pcg.games import get_game, get_game_spec, register_game_spec, registered_games, registry
from gvgai_pcg.generators import generate_level, registered_generators
from gvgai_pcg.generators.validation import playability_problems
from gvgai_pcg.levels import LEVEL_FORMATS, Level, LevelFormatError
from tests.games import toy_game

RIGHT = toy_game.Walk.actions.index("RIGHT")


@pytest.fixture
def toy():
    """The toy game registered for one test, the registry as it was afterwards."""
    tables = (registry._SPECS, registry._GAMES, registry._RULES, registry._GENERATORS)
    saved = [dict(table) for table in tables]
    register_game_spec(toy_game.SPEC)
    yield "toy"
    gym.registry.pop(env_id("Toy"), None)
    for table, before in zip(tables, saved, strict=True):
        table.clear()
        table.update(before)


class FakeEntryPoint:
    def __init__(self, name: str, value: str, target) -> None:
        self.name, self.value, self._target = name, value, target

    def load(self):
        return self._target


def test_a_registered_game_is_known_everywhere(toy):
    assert toy in registered_games() and toy in registered_generators()
    assert get_game_spec(toy) is toy_game.SPEC and get_game(toy).name == toy
    assert LEVEL_FORMATS[toy] == toy_game.SPEC.level_format
    level = Level.parse(toy_game.LEVEL_TEXT, toy)
    assert (level.width, level.height) == (7, 5)
    with pytest.raises(LevelFormatError, match="not in the toy legend"):
        Level.parse("wAx\n", toy)
    generated = generate_level(toy, 0.5, 3)
    assert generated == generate_level(toy, 0.5, 3) and generated.seed == 3
    assert playability_problems(generated) == []  # the toy declares no checks


def test_an_unknown_game_names_the_registered_ones(toy):
    with pytest.raises(ValueError, match="unknown game 'pong'; registered games are: .*toy"):
        get_game_spec("pong")


def test_a_second_game_of_the_same_name_is_refused(toy):
    other = toy_game.PLUGIN_SPEC
    clash = type(other)(**{**other.__dict__, "name": "toy", "level_format": toy_game.toy_format()})
    with pytest.raises(ValueError, match="already registered"):
        register_game_spec(clash)


def test_a_game_from_an_entry_point(toy, monkeypatch):
    plugins = [FakeEntryPoint("toyagain", "toy_pkg:SPEC", toy_game.PLUGIN_SPEC)]
    monkeypatch.setattr(
        plugins_module,
        "entry_points",
        lambda group: plugins if group == registry.GAME_ENTRY_POINT_GROUP else [],
    )
    monkeypatch.setattr(registry, "_read_game_entry_points", False)  # as in a fresh process
    assert "toyagain" in registered_games()
    assert get_game("toyagain").name == "toyagain" and get_game("toy").name == "toy"
    assert generate_level("toyagain", 1.0, 0).game == "toyagain"


def test_the_torchrl_env_plays_it(toy):
    level = Level.parse(toy_game.LEVEL_TEXT, toy, name="toy_walk")
    env = GVGAIEnv(toy, num_envs=3, levels=level, max_steps=10)
    check_env_specs(env)
    start = env.reset()
    assert start.get("tiles").shape == (3, 3, 5, 7)

    def walk_right(td):
        return td.set("action", torch.full((3,), RIGHT))

    steps = env.rollout(4, policy=walk_right, auto_reset=False, tensordict=start)  # A...g: four steps right
    assert steps.get(("next", "reward")).sum((1, 2)).tolist() == [1.0, 1.0, 1.0]
    assert steps.get(("next", "won")).reshape(3, 4)[:, -1].all()


def test_a_ppcg_env_generates_its_levels(toy):
    env = RowResetTransformedEnv(
        GVGAIEnv(toy, num_envs=8, levels=GeneratedLevels(toy), max_steps=5),
        DifficultyTransform("progressive", alpha=0.1, game=toy),
    )
    check_env_specs(env)
    env.rollout(12, break_when_any_done=False)
    names = {level.name for level in env.base_env.current_levels}
    assert all(name.startswith("toy_d") for name in names)


def test_the_gymnasium_api_plays_it(toy):
    assert env_id("Toy") in register_envs()
    env = gym.make(env_id("Toy"), regimen="pcg", difficulty=0.5, max_steps=8)
    observation, info = env.reset(seed=1)
    assert observation.shape == (3, 5, 7) and env.action_space.n == len(toy_game.Walk.actions)
    for _ in range(8):
        observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
        if terminated or truncated:
            break
    assert terminated or truncated
    env.close()


def test_one_a2c_training_batch(toy, tmp_path):
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir
    from gvgai_pcg.rl import train

    overrides = [
        "game.name=toy",
        "regimen=pcg",
        "regimen.difficulty=0.5",
        "env.num_envs=4",
        "env.max_steps=10",
        "total_frames=20",
        "log.every_episodes=4",
        "log.curve=false",
        f"out_dir={tmp_path}",
    ]
    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        cfg = compose("config", overrides=overrides)
    result = train(cfg, tmp_path / cfg.run_name)
    assert result.frames == 20 and result.model_path.exists()
