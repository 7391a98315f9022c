"""A learner defined outside the package (as a plug-in would be): one module (this) plus one yaml
(toy_learner.yaml): A2C's loss with plain SGD. ``SPEC`` is what an entry point of
``gvgai_pcg.learners`` would load."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import torch

from gvgai_pcg.config import Integer, Number
from gvgai_pcg.rl.a2c_loss import A2CLoss
from gvgai_pcg.rl.learners import LearnerSpec
from gvgai_pcg.rl.learners.base import Learner, Update


class SgdA2C(Learner):
    def __init__(self, algo, net, actor_critic) -> None:
        super().__init__(algo, net, actor_critic)
        self.loss_module = A2CLoss(actor_critic)
        self.optimizer = torch.optim.SGD(net.parameters(), lr=algo["lr"])
        self.updates = 0

    def update(self, rollout, check) -> Update:
        losses = self.loss_module(rollout)
        loss = losses["loss_objective"] + losses["loss_critic"] + losses["loss_entropy"]
        self.optimizer.zero_grad()
        loss.backward()
        check(loss, torch.nn.utils.clip_grad_norm_(self.net.parameters(), 1.0))
        self.optimizer.step()
        self.updates += 1
        return Update(losses["loss_objective"].detach(), losses["value_loss"], losses["entropy"])

    def state_dict(self) -> dict[str, Any]:
        return {"sgd": self.optimizer.state_dict(), "updates": self.updates}

    def load_state_dict(self, state: dict[str, Any]) -> None:
        self.optimizer.load_state_dict(state["sgd"])
        self.updates = state["updates"]


SPEC = LearnerSpec(
    name="toysgd",
    learner=SgdA2C,
    schema={"n_steps": Integer(1), "lr": Number(0.0, low_open=True)},
    config=Path(__file__).with_name("toy_learner.yaml"),
)
