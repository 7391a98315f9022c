"""A2C as the study ran it (OpenAI Baselines semantics, GENERATORS.md §3; ``conf/algo/a2c.yaml``).

One update per rollout of ``n_steps`` steps: n-step returns and the three losses (``A2CLoss``),
one RMSprop step with the gradient norm clipped. From 24 envs the rollout keeps its acting
passes' graph and the loss reuses it (``gvgai_pcg.rl.rollout``). Its checkpoint holds the RMSprop
state, as it always has.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import torch
from tensordict import TensorDictBase
from tensordict.nn import TensorDictModule
from torch import nn

from gvgai_pcg.config_rules import Integer, Number
from gvgai_pcg.curricula.signals import TRAIN_MASK
from gvgai_pcg.rl.a2c_loss import A2CLoss
from gvgai_pcg.rl.learners.base import Learner, Update, UpdateCheck
from gvgai_pcg.rl.learners.spec import LearnerSpec


class A2C(Learner):
    keep_acting_graph = None  # the rollout's default: keep it from 24 envs

    def __init__(self, algo: Mapping[str, Any], net: nn.Module, actor_critic: TensorDictModule) -> None:
        super().__init__(algo, net, actor_critic)
        self.loss_module = A2CLoss(actor_critic, algo["gamma"], algo["entropy_coef"], algo["value_coef"])
        self.optimizer = torch.optim.RMSprop(
            net.parameters(), lr=algo["lr"], alpha=algo["rmsprop_alpha"], eps=algo["rmsprop_eps"]
        )
        self.max_grad_norm = algo["max_grad_norm"]

    def update(self, rollout: TensorDictBase, check: UpdateCheck) -> Update:
        losses = self.loss_module(rollout)
        signals = {key: losses[key] for key in ("advantage", "value_target", "state_value")}
        mask = rollout.get(TRAIN_MASK, None)
        if mask is not None and not bool(mask.any()):  # a curriculum's mask without a step: no step
            return Update.untrained(signals)
        loss = losses["loss_objective"] + losses["loss_critic"] + losses["loss_entropy"]
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        grad_norm = torch.nn.utils.clip_grad_norm_(self.net.parameters(), self.max_grad_norm)
        check(loss, grad_norm)  # before it is applied
        self.optimizer.step()
        return Update(losses["loss_objective"].detach(), losses["value_loss"], losses["entropy"], signals)

    def state_dict(self) -> dict[str, Any]:
        return self.optimizer.state_dict()

    def load_state_dict(self, state: dict[str, Any]) -> None:
        self.optimizer.load_state_dict(state)


SPEC = LearnerSpec(
    name="a2c",
    learner=A2C,
    schema={
        "n_steps": Integer(1),
        "gamma": Number(0.0, 1.0),
        "lr": Number(0.0, low_open=True),
        "entropy_coef": Number(0.0),
        "value_coef": Number(0.0),
        "max_grad_norm": Number(0.0, low_open=True),
        "rmsprop_alpha": Number(0.0, 1.0),
        "rmsprop_eps": Number(0.0, low_open=True),
    },
    run_tag="",  # the study's learner: run names stay those of the published runs
    description="A2C as the study ran it (Baselines semantics, RMSprop)",
)
