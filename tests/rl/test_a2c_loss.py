"""The A2C returns and losses against small hand-computed examples."""

from __future__ import annotations

import math

import pytest
import torch
from tensordict import TensorDict
from tensordict.nn import TensorDictModule
from torch import nn

from gvgai_pcg.rl.a2c_loss import A2CLoss, nstep_returns


def test_returns_bootstrap_from_the_last_value():
    rewards = torch.tensor([[1.0, 0.0, 2.0]])
    bootstrap = torch.tensor([[9.0, 9.0, 10.0]])  # only the last entry is read: no episode ended
    no = torch.zeros(1, 3, dtype=torch.bool)
    returns = nstep_returns(rewards, bootstrap, no, no, gamma=0.5)
    # R2 = 2 + .5*10 = 7; R1 = 0 + .5*7 = 3.5; R0 = 1 + .5*3.5 = 2.75
    assert returns.tolist() == [[2.75, 3.5, 7.0]]


def test_returns_are_cut_at_a_real_end_and_bootstrap_at_a_truncation():
    rewards = torch.tensor([[1.0, 1.0, 1.0, 1.0], [1.0, 1.0, 1.0, 1.0]])
    bootstrap = torch.tensor([[0.0, 4.0, 0.0, 8.0], [0.0, 4.0, 0.0, 8.0]])
    done = torch.tensor([[False, True, False, False], [False, True, False, False]])
    terminated = torch.tensor([[False, True, False, False], [False, False, False, False]])
    returns = nstep_returns(rewards, bootstrap, terminated, done, gamma=0.5)
    # env 0 terminated at t=1: R1 = 1, R0 = 1.5; then R3 = 1 + 4 = 5, R2 = 3.5
    # env 1 truncated at t=1: R1 = 1 + .5*4 = 3 (value of its final observation), R0 = 2.5
    assert returns.tolist() == [[1.5, 1.0, 3.5, 5.0], [2.5, 3.0, 3.5, 5.0]]


def test_a_terminal_last_step_does_not_bootstrap():
    done = torch.tensor([[False, True]])
    returns = nstep_returns(torch.tensor([[1.0, 2.0]]), torch.tensor([[0.0, 100.0]]), done, done, gamma=0.9)
    assert returns.tolist() == [[pytest.approx(1.0 + 0.9 * 2.0), 2.0]]


class TableNet(nn.Module):
    """Logits and value looked up from the observation's id (obs ``[N, 1, 1, 1]`` uint8)."""

    def __init__(self, logits: torch.Tensor, values: torch.Tensor) -> None:
        super().__init__()
        self.logits = nn.Parameter(logits)
        self.values = nn.Parameter(values)

    def forward(self, obs: torch.Tensor):
        idx = obs.reshape(-1).long()
        return self.logits[idx], self.values[idx].unsqueeze(-1)


class OtherModule(TensorDictModule):
    """Not a plain TensorDictModule: the loss calls it through a tensordict."""


@pytest.mark.parametrize("wrapper", [TensorDictModule, OtherModule])
def test_losses_match_a_hand_computation(wrapper):
    # two observation ids: 0 (logits [0, ln 3] -> probs [1/4, 3/4]) and 1 (uniform over 2 actions)
    net = TableNet(torch.tensor([[0.0, math.log(3.0)], [0.0, 0.0]]), torch.tensor([1.0, 2.0]))
    loss = A2CLoss(wrapper(net, ["tiles"], ["logits", "state_value"]), gamma=0.5)
    assert (loss._net is net) == (wrapper is TensorDictModule)  # a plain one is called directly
    assert all(not key.startswith("_net") for key in loss.state_dict())
    obs = torch.tensor([[0, 1]], dtype=torch.uint8).reshape(1, 2, 1, 1, 1)
    next_obs = torch.tensor([[1, 0]], dtype=torch.uint8).reshape(1, 2, 1, 1, 1)
    false = torch.zeros(1, 2, 1, dtype=torch.bool)
    rollout = TensorDict(
        {
            "tiles": obs,
            "action": torch.tensor([[1, 0]]),
            "next": {
                "tiles": next_obs,
                "reward": torch.tensor([[[1.0], [0.0]]]),
                "done": false,
                "terminated": false,
                "truncated": false,
            },
        },
        batch_size=[1, 2],
    )
    out = loss(rollout)
    # bootstrap V(next of last) = V(0) = 1: R1 = 0 + .5*1 = .5; R0 = 1 + .5*.5 = 1.25
    # values [1, 2] -> advantages [.25, -1.5]; log pi: [ln 3/4, ln 1/2]
    pg = (0.25 * -math.log(0.75) + -1.5 * -math.log(0.5)) / 2
    value_loss = 0.5 * ((1 - 1.25) ** 2 + (2 - 0.5) ** 2) / 2
    h0 = -(0.25 * math.log(0.25) + 0.75 * math.log(0.75))
    entropy = (h0 + math.log(2.0)) / 2
    assert out["loss_objective"].item() == pytest.approx(pg, rel=1e-6)
    assert out["value_loss"].item() == pytest.approx(value_loss, rel=1e-6)
    assert out["loss_critic"].item() == pytest.approx(0.5 * value_loss, rel=1e-6)
    assert out["entropy"].item() == pytest.approx(entropy, rel=1e-6)
    assert out["loss_entropy"].item() == pytest.approx(-0.01 * entropy, rel=1e-6)
    total = out["loss_objective"] + out["loss_critic"] + out["loss_entropy"]
    total.backward()
    # the value gradient flows only through V(s_t), not through the returns: d/dV0 = .5 * (V0 - R0) / 2
    assert net.values.grad[0].item() == pytest.approx(0.5 * (1 - 1.25) / 2, rel=1e-6)


def test_a_truncated_step_bootstraps_from_its_final_observation():
    net = TableNet(torch.zeros(3, 2), torch.tensor([0.0, 0.0, 10.0]))
    loss = A2CLoss(TensorDictModule(net, ["tiles"], ["logits", "state_value"]), gamma=0.5)
    obs = torch.tensor([0, 0], dtype=torch.uint8).reshape(1, 2, 1, 1, 1)
    next_obs = torch.tensor([2, 0], dtype=torch.uint8).reshape(1, 2, 1, 1, 1)  # 2: the final observation
    truncated = torch.tensor([[[True], [False]]])
    rollout = TensorDict(
        {
            "tiles": obs,
            "action": torch.tensor([[0, 0]]),
            "next": {
                "tiles": next_obs,
                "reward": torch.zeros(1, 2, 1),
                "done": truncated,
                "terminated": torch.zeros(1, 2, 1, dtype=torch.bool),
                "truncated": truncated,
            },
        },
        batch_size=[1, 2],
    )
    out = loss(rollout)
    # R0 = .5 * V(final obs) = 5, R1 = .5 * V(0) = 0; values are 0 -> value loss .5 * (25 + 0) / 2
    assert out["value_loss"].item() == pytest.approx(6.25)
