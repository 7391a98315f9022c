"""A new curriculum is one module plus one yaml: the toy of ``toy_curriculum.py``, registered from
outside the package (in-process, and through the ``gvgai_pcg.curricula`` entry-point group), is a
regimen everywhere: its config composes and is checked, its source is fed by the signals of real
rollouts, and it trains through ``gvgai_pcg.rl.train`` and ``gvgai-pcg train``."""

from __future__ import annotations

import pytest
import torch
from torch import nn

import gvgai_pcg.plugins as plugins_module
from gvgai_pcg.config import ConfigError, compose_config
from gvgai_pcg.curricula import get_curriculum, register_curriculum, registered_curricula, registry
from gvgai_pcg.curricula.signals import LevelSignals
from gvgai_pcg.rl.environment import EnvFactory, curriculum_run
from gvgai_pcg.rl.rollout import ActingRollouts
from tests.curricula import toy_curriculum

SMALL = ["game=zelda", "env.num_envs=4", "env.max_steps=6", "log.every_episodes=4", "log.curve=false"]


@pytest.fixture
def toy(monkeypatch):
    """The toy curriculum registered for one test, forgotten afterwards (ticks eager: these
    tests are about the curriculum, and compiling would take a minute)."""
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    register_curriculum(toy_curriculum.CURRICULUM)
    yield toy_curriculum.CURRICULUM
    registry.unregister_curriculum("toyreplay")


class FakeEntryPoint:
    name, value = "toyreplay", "toy_pkg:CURRICULUM"

    def load(self):
        return toy_curriculum.CURRICULUM


def test_a_curriculum_from_an_entry_point(monkeypatch):
    monkeypatch.setattr(plugins_module, "entry_points", lambda group: [FakeEntryPoint()])
    try:
        assert get_curriculum("toyreplay") is toy_curriculum.CURRICULUM
        assert "toyreplay" in registered_curricula()
    finally:
        registry.unregister_curriculum("toyreplay")


def test_an_unknown_curriculum_names_the_registered_ones(toy):
    with pytest.raises(ValueError, match="unknown regimen 'nosuch'; valid regimens are: .*ppcg.*toyreplay"):
        get_curriculum("nosuch")


def test_a_second_curriculum_of_a_taken_name_is_refused(toy):
    clash = type("Clash", (toy_curriculum.ToyReplay,), {})()
    with pytest.raises(ValueError, match="already registered"):
        register_curriculum(clash)


def test_its_yaml_composes_and_its_schema_checks_it(toy):
    cfg = compose_config([*SMALL, "regimen=toyreplay", "regimen.pool=3"])
    assert dict(cfg.regimen) == {"name": "toyreplay", "difficulty": 0.5, "pool": 3, "tag": "toyreplay3"}
    assert cfg.run_name.startswith("zelda-toyreplay3-")
    with pytest.raises(ConfigError, match=r"regimen.pool=0: expected an integer in \[1, 64\]"):
        compose_config([*SMALL, "regimen=toyreplay", "regimen.pool=0"])


class Uniform(nn.Module):
    """A policy that knows nothing: equal logits, zero value."""

    def __init__(self, actions: int) -> None:
        super().__init__()
        self.actions = actions

    def forward(self, obs):
        return torch.zeros(obs.shape[0], self.actions), torch.zeros(obs.shape[0], 1)


def test_rollouts_tell_it_what_happened_on_each_level(toy):
    cfg = compose_config([*SMALL, "regimen=toyreplay", "regimen.pool=3"])
    run = curriculum_run(cfg.regimen, "zelda")
    state = run.state
    env = EnvFactory("zelda", cfg.regimen, 4, "tiles", 6, "cpu", 0, run=run)()
    rollouts = ActingRollouts(env, Uniform(env.action_spec.space.n), "tiles", n_steps=7)
    signals_of = LevelSignals()
    signals = signals_of(rollouts.collect(), advantage=torch.ones(4, 7))
    assert set(signals["level_seed"].tolist()) <= {0, 1, 2}  # the rollout kept each step's level
    assert signals["finished"].any() and (signals["length"][signals["finished"]] == 6).all()
    assert torch.equal(signals["advantage_positive"], torch.ones(len(signals)))
    assert run.learns
    run.observe(signals)  # the run's route: its source around the shared state
    assert int(state.finished.sum()) == int(signals["finished"].sum()) > 0  # the shared state moved
    env.close()


def test_it_trains_through_the_python_api(toy, tmp_path):
    from gvgai_pcg.rl import train

    cfg = compose_config([*SMALL, "regimen=toyreplay", "total_frames=200", f"out_dir={tmp_path}"])
    result = train(cfg, tmp_path / cfg.run_name)
    assert result.frames >= 200 and result.model_path.exists()


def test_it_trains_through_the_command_line(toy, tmp_path):
    from gvgai_pcg.commands.train import run_raw

    assert run_raw([*SMALL, "regimen=toyreplay", "total_frames=100", f"out_dir={tmp_path}"]) == 0
    assert (tmp_path / "zelda-toyreplay4-tiles-compact-seed0" / "model.pt").is_file()
