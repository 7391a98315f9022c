"""Learners are plug-ins: the registry, each learner's own config keys, a learner registered from
outside the package training through the shared loop, PPO's update, and run names that tell the
learners apart while A2C's stay those of the published runs."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import torch
import yaml
from omegaconf import OmegaConf
from tensordict import TensorDict

import gvgai_pcg.plugins as plugins_module
from gvgai_pcg.config import ConfigError, checked_config, compose_config, config_dir
from gvgai_pcg.curricula.base import CurriculumRun
from gvgai_pcg.curricula.signals import TRAIN_MASK
from gvgai_pcg.envs import LevelSource
from gvgai_pcg.rl import train
from gvgai_pcg.rl.learners import get_learner_spec, learner_class, register_learner, registered_learners
from gvgai_pcg.rl.learners import registry as learner_registry
from gvgai_pcg.rl.learners.ppo import PPO
from gvgai_pcg.rl.models import as_tensordict_module, make_actor_critic
from gvgai_pcg.rundir.run_log import read_log
from gvgai_pcg.rundir.update_log import read_updates
from tests.rl import toy_learner

REPO = Path(__file__).resolve().parents[2]
TINY = ["regimen=lv", "env.num_envs=4", "env.max_steps=20", "log.backends=[csv]", "log.curve=false"]


@pytest.fixture
def toy():
    saved = dict(learner_registry._SPECS)
    register_learner(toy_learner.SPEC)
    yield toy_learner.SPEC.name
    learner_registry._SPECS.clear()
    learner_registry._SPECS.update(saved)


class FakeEntryPoint:
    name, value = "toysgd", "toy_pkg:SPEC"

    def load(self):
        return toy_learner.SPEC


def test_the_built_in_learners_and_an_unknown_name():
    assert {"a2c", "ppo"} <= set(registered_learners())
    with pytest.raises(ValueError, match="unknown learner 'sac' .*registered learners are: a2c, ppo"):
        get_learner_spec("sac")
    with pytest.raises(ConfigError, match=r"^algo.name='sac': expected one of a2c, ppo"):
        compose_config(["algo.name=sac"])


def test_each_learner_checks_its_own_keys():
    with pytest.raises(ConfigError, match="algo.epochs=0: expected an integer >= 1"):
        compose_config(["algo=ppo", "algo.epochs=0"])
    with pytest.raises(
        ConfigError,
        match=r"algo.rmsprop_alpha=0.99: unknown key; the keys of algo are name, n_steps, gamma, gae_lambda",
    ):
        compose_config(["algo=ppo", "+algo.rmsprop_alpha=0.99"])
    assert compose_config(["algo=ppo"]).algo.lr == 5e-4


def test_a_learner_from_an_entry_point(monkeypatch):
    saved = dict(learner_registry._SPECS)
    monkeypatch.setattr(
        plugins_module,
        "entry_points",
        lambda group: [FakeEntryPoint()] if group == learner_registry.LEARNER_ENTRY_POINT_GROUP else [],
    )
    try:
        assert "toysgd" in registered_learners() and learner_class("toysgd") is toy_learner.SgdA2C
    finally:
        learner_registry._SPECS.clear()
        learner_registry._SPECS.update(saved)


def test_a_learner_registered_from_outside_trains_and_resumes(toy, tmp_path, make_config):
    cfg = make_config([*TINY, "total_frames=16", f"out_dir={tmp_path}"])
    cfg.algo = {"name": toy, "n_steps": 2, "lr": 0.01}  # what its conf/algo/toysgd.yaml would hold
    cfg = checked_config(cfg)
    assert cfg.run_name.endswith("-compact-toysgd-seed0")  # a learner's run directory of its own
    result = train(cfg, tmp_path / cfg.run_name)
    checkpoint = torch.load(result.checkpoint_path, weights_only=False)
    assert checkpoint["optimizer"]["updates"] == 2  # what the learner's checkpoint holds
    cfg.total_frames = 32
    result = train(cfg, tmp_path / cfg.run_name)
    assert torch.load(result.checkpoint_path, weights_only=False)["optimizer"]["updates"] == 4


def test_a_learner_from_outside_is_one_module_plus_one_yaml_and_trains_from_the_command_line(
    toy, tmp_path, monkeypatch
):
    from gvgai_pcg.commands.train import run_raw

    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    cfg = compose_config([*TINY, "algo=toysgd"])  # its yaml, from the config store
    assert dict(cfg.algo) == {"name": "toysgd", "n_steps": 2, "lr": 0.01}
    assert run_raw([*TINY, "algo=toysgd", "total_frames=16", f"out_dir={tmp_path}"]) == 0
    (run,) = tmp_path.iterdir()
    assert run.name.endswith("-toysgd-seed0") and (run / "model.pt").is_file()


def _rollout(batch: int, steps: int, obs_shape: tuple[int, int, int], actions: int) -> TensorDict:
    generator = torch.Generator().manual_seed(0)
    obs = torch.randint(0, 2, (batch, steps + 1, *obs_shape), generator=generator, dtype=torch.uint8)
    done = torch.zeros(batch, steps, 1, dtype=torch.bool)
    done[0, 1] = True
    truncated = torch.zeros_like(done)
    truncated[1, 2] = True
    done |= truncated
    return TensorDict(
        {
            "tiles": obs[:, :-1],
            "action": torch.randint(0, actions, (batch, steps), generator=generator),
            "logits": torch.randn(batch, steps, actions, generator=generator),
            "state_value": torch.zeros(batch, steps, 1),
            "next": {
                "tiles": obs[:, 1:],
                "reward": torch.randn(batch, steps, 1, generator=generator),
                "done": done,
                "terminated": done & ~truncated,
                "truncated": truncated,
            },
        },
        batch_size=(batch, steps),
    )


def test_one_ppo_update():
    torch.manual_seed(0)
    net = make_actor_critic("compact", "tiles", (5, 7, 9), 6, 32)
    algo = dict(compose_config(["algo=ppo"]).algo, epochs=2, minibatches=3)
    learner = PPO(algo, net, as_tensordict_module(net, "tiles"))
    before = [p.detach().clone() for p in net.parameters()]
    checks = []
    update = learner.update(_rollout(4, 6, (5, 7, 9), 6), lambda loss, norm: checks.append((loss, norm)))
    assert len(checks) == 2 * 3  # the divergence guard sees every optimizer step
    assert all(torch.isfinite(loss) and torch.isfinite(norm) for loss, norm in checks)
    assert any(not torch.equal(a, b) for a, b in zip(before, net.parameters(), strict=True))
    assert update.stacked().shape == (3,) and bool(update.stacked().isfinite().all())
    assert 0 < update.entropy <= torch.log(torch.tensor(6.0)) + 1e-5
    for key in ("advantage", "value_target", "state_value"):
        assert update.signals[key].shape == (4, 6)
    assert "exp_avg" in next(iter(learner.state_dict()["state"].values()))  # Adam's state


@pytest.mark.parametrize("masked", [False, True], ids=["one-step batch", "one step kept by the mask"])
def test_a_ppo_update_on_a_single_step_is_finite_and_takes_its_step(masked):
    torch.manual_seed(0)
    net = make_actor_critic("compact", "tiles", (5, 7, 9), 6, 32)
    algo = dict(compose_config(["algo=ppo"]).algo, epochs=1, minibatches=1)
    learner = PPO(algo, net, as_tensordict_module(net, "tiles"))
    rollout = _rollout(2, 3, (5, 7, 9), 6) if masked else _rollout(2, 3, (5, 7, 9), 6)[:1, :1]
    if masked:  # PLR⊥ keeps the steps of replayed levels only: here one
        mask = torch.zeros(2, 3, dtype=torch.bool)
        mask[0, 2] = True
        rollout.set(TRAIN_MASK, mask)
    before = [p.detach().clone() for p in net.parameters()]
    checks = []
    update = learner.update(rollout, lambda loss, norm: checks.append((loss, norm)))
    assert len(checks) == 1 and all(torch.isfinite(loss) and torch.isfinite(norm) for loss, norm in checks)
    assert bool(update.stacked().isfinite().all())
    assert any(not torch.equal(a, b) for a, b in zip(before, net.parameters(), strict=True))


def test_a_ppo_run_of_one_env_and_one_step_per_batch_trains_without_diverging(tmp_path):
    argv = ["algo=ppo", "regimen=lv", "env.num_envs=1", "algo.n_steps=1", "algo.minibatches=1"]
    cfg = compose_config(
        [*argv, "env.max_steps=10", "total_frames=6", "log.curve=false", f"out_dir={tmp_path}"]
    )
    result = train(cfg, tmp_path / "run")
    assert result.frames == 6 and result.model_path.is_file()
    assert all(math.isfinite(row["value_loss"]) for row in read_updates(result.updates_path))


@pytest.mark.parametrize(
    ("overrides", "steps"),
    [(["env.num_envs=1", "algo.n_steps=1"], "1 step "), (["env.num_envs=2", "algo.n_steps=3"], "6 steps ")],
)
def test_ppo_refuses_more_minibatches_than_a_batch_has_steps(overrides, steps):
    with pytest.raises(ConfigError, match=rf"^algo.minibatches=8: expected at most the {steps}of a batch"):
        compose_config(["algo=ppo", *overrides])
    compose_config(["algo=ppo", *overrides[:1], "algo.n_steps=8"])  # 8 steps or more: accepted


def test_run_names_tell_learners_apart_and_keep_a2cs():
    for condition in ("zelda-ppcg", "frogs-pcg0.5", "solarfox-lv0-3"):  # each kind of regimen tag
        a2c = compose_config([f"condition={condition}"]).run_name
        ppo = compose_config([f"condition={condition}", "algo=ppo"]).run_name
        assert "a2c" not in a2c and ppo == a2c.replace("-seed0", "-ppo-seed0") and ppo != a2c


def test_published_runs_keep_their_names():
    """Each published run's saved config gives its directory's name under today's run_name."""
    template = yaml.safe_load((Path(config_dir()) / "config.yaml").read_text())["run_name"]
    runs = sorted((REPO / "results" / "small" / "runs").glob("*/config.yaml"))
    assert runs, "no published runs to check"
    for path in runs:
        saved = yaml.safe_load(path.read_text())
        saved["run_name"] = template
        assert OmegaConf.create(saved).run_name == path.parent.name


class LearningSource(LevelSource):
    """A level source with an ``observe`` hook, standing in for a curriculum's: ``source``'s levels."""

    def __init__(self, source: LevelSource) -> None:
        self.source, self.seen, self.game = source, [], source.game
        # its levels are ``source``'s, and so are the facts about them
        self.prepare_ahead, self.depends_on_difficulty = source.prepare_ahead, source.depends_on_difficulty
        self.levels_recur, self.level_difficulties = source.levels_recur, source.level_difficulties

    def next_levels(self, env_indices, episode_seeds, difficulties):
        return self.source.next_levels(env_indices, episode_seeds, difficulties)

    def observe(self, signals) -> None:
        self.seen.append(signals)


def test_a_short_ppo_run_logs_its_updates_and_feeds_the_curriculum(tmp_path, monkeypatch, capsys):
    sources = []
    level_source = CurriculumRun.source

    def learning_source(self):
        sources.append(LearningSource(level_source(self)))
        return sources[-1]

    monkeypatch.setattr(CurriculumRun, "source", learning_source)
    overrides = [
        *TINY,
        "algo=ppo",
        "algo.n_steps=8",
        "algo.minibatches=2",
        "log.curve=true",
        f"out_dir={tmp_path}",
    ]
    cfg = compose_config([*overrides, "total_frames=64", "log.every_update_frames=64"])
    result = train(cfg, tmp_path / cfg.run_name)
    assert result.run_dir.name == "zelda-lv0-tiles-compact-ppo-seed0"
    assert read_log(result.log_path) == []  # no episode has ended in 64 frames of 20-step episodes
    assert "64 frames and no row in log.csv yet" in capsys.readouterr().err
    rows = read_updates(result.updates_path)
    assert [row["frames"] for row in rows] == [32, 64]  # the first update, then every 64 frames
    assert all(row["entropy"] > 0 for row in rows)
    assert result.curve_path.read_bytes()[:4] == b"\x89PNG"  # the updates' entropy, not a blank plot
    seen = [signals for source in sources for signals in source.seen]
    assert len(seen) == 2  # one batch of per-level signals after each update
    assert seen[0]["env"].tolist() == [0, 1, 2, 3]  # one level segment per env: no episode ended
    for key in ("advantage", "advantage_positive", "state_value", "value_loss", "level_seed", "return"):
        assert seen[0][key].shape == (4,)
    assert bool(seen[0]["value_loss"].isfinite().all())

    cfg = compose_config([*overrides, "total_frames=128", "log.every_update_frames=64"])
    result = train(cfg, tmp_path / cfg.run_name)  # resumes at 64 frames
    assert [row["frames"] for row in read_updates(result.updates_path)] == [32, 64, 96, 128]
