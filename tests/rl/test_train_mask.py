"""A curriculum's ``train_mask`` (PLR⊥: gradients from replayed levels only): the learners take
their losses over its steps, take no step where it has none, and are unchanged without one."""

from __future__ import annotations

import math

import pytest
import torch
from tensordict import TensorDict
from tensordict.nn import TensorDictModule

from gvgai_pcg.config import compose_config
from gvgai_pcg.curricula.signals import TRAIN_MASK, Feedback
from gvgai_pcg.envs import LevelSource
from gvgai_pcg.rl.a2c_loss import A2CLoss
from gvgai_pcg.rl.learners.a2c import A2C
from gvgai_pcg.rl.learners.ppo import PPO
from gvgai_pcg.rl.models import as_tensordict_module, make_actor_critic
from gvgai_pcg.rundir.run_log import RunLog, read_log
from gvgai_pcg.rundir.update_log import UpdateLog, mean_losses, read_updates
from tests.curricula.test_signals import run_of
from tests.rl.test_a2c_loss import TableNet
from tests.rl.test_learners import _rollout


def two_step_rollout() -> TensorDict:
    """The rollout of ``test_losses_match_a_hand_computation`` (advantages [.25, -1.5])."""
    false = torch.zeros(1, 2, 1, dtype=torch.bool)
    return TensorDict(
        {
            "tiles": torch.tensor([[0, 1]], dtype=torch.uint8).reshape(1, 2, 1, 1, 1),
            "action": torch.tensor([[1, 0]]),
            "next": {
                "tiles": torch.tensor([[1, 0]], dtype=torch.uint8).reshape(1, 2, 1, 1, 1),
                "reward": torch.tensor([[[1.0], [0.0]]]),
                "done": false,
                "terminated": false,
                "truncated": false,
            },
        },
        batch_size=[1, 2],
    )


def a2c_loss() -> A2CLoss:
    net = TableNet(torch.tensor([[0.0, math.log(3.0)], [0.0, 0.0]]), torch.tensor([1.0, 2.0]))
    return A2CLoss(TensorDictModule(net, ["tiles"], ["logits", "state_value"]), gamma=0.5)


def test_the_a2c_losses_are_means_over_the_masked_steps():
    rollout = two_step_rollout()
    unmasked = a2c_loss()(rollout)
    everything = a2c_loss()(rollout.clone().set(TRAIN_MASK, torch.ones(1, 2, dtype=torch.bool)))
    for key in ("loss_objective", "value_loss", "entropy"):
        assert everything[key].item() == pytest.approx(unmasked[key].item(), rel=1e-6)
    first = a2c_loss()(rollout.clone().set(TRAIN_MASK, torch.tensor([[True, False]])))
    # step 0 only: advantage .25, log pi = ln 3/4, V - R = 1 - 1.25, entropy of [1/4, 3/4]
    assert first["loss_objective"].item() == pytest.approx(0.25 * -math.log(0.75), rel=1e-6)
    assert first["value_loss"].item() == pytest.approx(0.5 * 0.25**2, rel=1e-6)
    assert first["entropy"].item() == pytest.approx(
        -(0.25 * math.log(0.25) + 0.75 * math.log(0.75)), rel=1e-6
    )
    assert torch.equal(first["advantage"], unmasked["advantage"])  # the curriculum's signals: every step


def learner_and_rollout(name: str):
    torch.manual_seed(0)
    net = make_actor_critic("compact", "tiles", (5, 7, 9), 6, 32)
    algo = compose_config([f"algo={name}"]).algo
    if name == "ppo":
        algo = dict(algo, epochs=1, minibatches=2)
    learner = (PPO if name == "ppo" else A2C)(algo, net, as_tensordict_module(net, "tiles"))
    return learner, net, _rollout(4, 6, (5, 7, 9), 6)


@pytest.mark.parametrize("name", ["a2c", "ppo"])
def test_a_mask_without_a_step_takes_no_optimizer_step_but_gives_the_signals(name):
    learner, net, rollout = learner_and_rollout(name)
    before = [p.detach().clone() for p in net.parameters()]
    checks = []
    rollout.set(TRAIN_MASK, torch.zeros(4, 6, dtype=torch.bool))
    update = learner.update(rollout, lambda loss, norm: checks.append(loss))
    assert checks == [] and all(torch.equal(a, b) for a, b in zip(before, net.parameters(), strict=True))
    assert update.signals["advantage"].shape == (4, 6)  # still scored by the curriculum
    # nothing was learnt: the losses are NaN (left out of the log's means), not zeros
    assert all(math.isnan(value) for value in update.stacked().tolist())


def test_a_log_row_averages_the_updates_that_trained_and_is_nan_without_one(tmp_path):
    trained = torch.tensor([0.5, 2.0, 1.0])
    untrained = torch.full((3,), math.nan)
    assert mean_losses([trained, untrained, trained * 3]) == pytest.approx([1.0, 4.0, 2.0])
    assert all(math.isnan(value) for value in mean_losses([untrained, untrained]))
    # a row of NaN losses is written and read back as NaN (not taken for a row cut short)
    log = RunLog(tmp_path, [], resume_frames=None)
    log.write({"frames": 10, "episodes": 1, "mean_score": 1.0, "policy_loss": math.nan})
    log.write({"frames": 20, "episodes": 2, "mean_score": 2.0, "policy_loss": 0.5})
    log.close()
    rows = read_log(tmp_path / "log.csv")
    assert len(rows) == 2 and math.isnan(rows[0]["policy_loss"]) and rows[1]["policy_loss"] == 0.5
    updates = UpdateLog(tmp_path, [], resume_frames=None)
    updates.write({"frames": 10, "updates": 1, "policy_loss": math.nan})
    updates.close()
    assert math.isnan(read_updates(tmp_path / "updates.csv")[0]["policy_loss"])


@pytest.mark.parametrize("name", ["a2c", "ppo"])
def test_a_mask_with_steps_trains_on_them(name):
    learner, net, rollout = learner_and_rollout(name)
    before = [p.detach().clone() for p in net.parameters()]
    mask = torch.zeros(4, 6, dtype=torch.bool)
    mask[1] = True
    checks = []
    learner.update(rollout.set(TRAIN_MASK, mask), lambda loss, norm: checks.append(loss))
    assert checks and any(not torch.equal(a, b) for a, b in zip(before, net.parameters(), strict=True))


class Plain(LevelSource):
    """A source that learns and marks no steps (``trains_on`` left at ``LevelSource``'s None)."""

    game = "zelda"

    def next_levels(self, env_indices, episode_seeds, difficulties):
        return []

    def observe(self, signals):
        pass


def test_the_feedback_writes_the_sources_mask_and_nothing_without_one():
    class Marks(Plain):
        def trains_on(self, rollout):
            return torch.tensor([[True, False, True]])

    rollout = TensorDict({}, batch_size=[1, 3])
    Feedback(run_of(Marks())).mark_trained_steps(rollout)
    assert rollout[TRAIN_MASK].tolist() == [[True, False, True]]
    plain = TensorDict({}, batch_size=[1, 3])
    Feedback(run_of(Plain())).mark_trained_steps(plain)
    assert TRAIN_MASK not in plain.keys()
