"""The fused rollout (``gvgai_pcg.rl.fused``): the same rollouts and the same training as the
unfused path, bit for bit on one machine, whatever the curriculum restarts the finished envs with."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
import torch

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.rl import train
from gvgai_pcg.rl.environment import curriculum_run
from gvgai_pcg.rl.fused import FusedStep, fusable, fused_step
from gvgai_pcg.rl.models import make_actor_critic
from gvgai_pcg.rl.rollout import ActingRollouts
from tests.rl.conftest import needs_generated_levels


def _rollouts(fused: bool, obs: str, keep_graph: bool, compile_tick: bool, run=None, batches: int = 4):
    levels = run.source() if run is not None else "human"
    env = GVGAIEnv("zelda", 6, levels, obs, max_steps=9, seed=3, compile_tick=compile_tick)
    env = run.wrap(env) if run is not None else env
    shape = tuple(env.observation_spec[obs].shape[-3:])
    torch.manual_seed(0)
    net = make_actor_critic("compact", obs, shape, env.action_spec.space.n, 32)
    step = FusedStep(env, net, compile=compile_tick) if fused else None
    torch.manual_seed(5)
    rollouts = ActingRollouts(env, net, obs, 5, keep_graph=keep_graph, fused=step)
    return [rollouts.collect() for _ in range(batches)]


def _assert_same(unfused, fused) -> None:
    for a, b in zip(unfused, fused, strict=True):
        assert set(a.keys(True, True)) == set(b.keys(True, True))
        for key in a.keys(True, True):
            assert torch.equal(a.get(key).detach(), b.get(key).detach()), key


@pytest.mark.parametrize(("obs", "keep_graph"), [("tiles", True), ("tiles", False), ("pixels", False)])
def test_fused_rollouts_are_the_unfused_ones_bit_for_bit(obs, keep_graph):
    unfused = _rollouts(False, obs, keep_graph, compile_tick=False)
    fused = _rollouts(True, obs, keep_graph, compile_tick=False)
    _assert_same(unfused, fused)
    done = torch.stack([r.get(("next", "done")) for r in fused])
    assert done.any() and not done.all()  # episodes ended (max_steps 9) and restarted within them
    assert fused[-1].get("logits").requires_grad == keep_graph


@needs_generated_levels
def test_fused_rollouts_restart_finished_envs_through_the_curriculum_as_unfused(make_config):
    regimen = make_config(["regimen=ppcg", "regimen.start=0.5"]).regimen  # d moves at finished episodes
    runs = [curriculum_run(regimen, "zelda") for _ in range(2)]
    unfused = _rollouts(False, "tiles", False, compile_tick=False, run=runs[0])
    fused = _rollouts(True, "tiles", False, compile_tick=False, run=runs[1])
    _assert_same(unfused, fused)
    assert runs[0].difficulty == runs[1].difficulty < 0.5  # the finished episodes moved d alike
    assert fused[-1].get(("next", "level_seed")).unique().numel() > 6  # new levels within a rollout


def test_what_cannot_roll_out_fused_is_said_in_one_line():
    env = GVGAIEnv("zelda", 4, "human", "tiles", seed=0, shards=2)
    assert "several threads" in fusable(env)
    assert fused_step("auto", env, torch.nn.Identity()) is None  # auto rolls out unfused (not faster)
    with pytest.raises(ValueError, match="rollout=fused: this env cannot roll out fused"):
        fused_step("fused", env, torch.nn.Identity())
    assert fused_step("unfused", GVGAIEnv("zelda", 4, compile_tick=False), torch.nn.Identity()) is None
    with pytest.raises(ValueError, match="needs a GVGAIEnv"):
        FusedStep(torch.nn.Identity(), torch.nn.Identity())


def _update_losses(make_config, tmp_path: Path, rollout: str, algo: str) -> list[dict]:
    overrides = ["regimen=lv0-3", "env.num_envs=4", "env.max_steps=6", "model.hidden=16", f"algo={algo}"]
    overrides += ["algo.n_steps=5"] if algo == "ppo" else []
    overrides += ["total_frames=120", "log.every_update_frames=1", "log.curve=false", f"rollout={rollout}"]
    cfg = make_config([*overrides, f"out_dir={tmp_path / rollout}"])
    result = train(cfg, tmp_path / rollout / cfg.run_name)
    with open(result.updates_path) as file:
        rows = list(csv.DictReader(file))
    return [{k: row[k] for k in ("frames", "policy_loss", "value_loss", "entropy")} for row in rows]


@pytest.mark.parametrize("algo", ["a2c", "ppo"])
def test_training_through_the_fused_rollout_gives_the_unfused_losses(make_config, tmp_path, algo):
    unfused = _update_losses(make_config, tmp_path, "unfused", algo)
    fused = _update_losses(make_config, tmp_path, "fused", algo)
    assert len(unfused) >= 2 and fused == unfused


@pytest.mark.slow  # compiles the acting pass, the draw and Zelda's tick together (a minute or two)
def test_the_compiled_fused_rollout_is_the_unfused_one():
    unfused = _rollouts(False, "tiles", True, compile_tick=True, batches=3)
    fused = _rollouts(True, "tiles", True, compile_tick=True, batches=3)
    _assert_same(unfused, fused)


def test_the_rollout_key_takes_three_values_and_may_be_missing_from_an_older_config(make_config):
    from omegaconf import OmegaConf

    from gvgai_pcg.config import ConfigError, checked_config

    assert checked_config(make_config(["rollout=fused"])).rollout == "fused"
    with pytest.raises(ConfigError, match="rollout='fast'"):
        checked_config(make_config(["rollout=fast"]))
    older = OmegaConf.to_container(make_config([]), resolve=True)
    del older["rollout"]
    checked_config(OmegaConf.create(older))  # a run's config from before the key is still valid
