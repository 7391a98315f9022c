"""PPO with TorchRL's ``ClipPPOLoss`` and ``GAE``, with the defaults of the UED libraries' Procgen
setting (``conf/algo/ppo.yaml``; docs/training.md).

One update per rollout of ``n_steps`` steps: GAE advantages and value targets of the rollout
(the weights that acted), the advantages normalised over the whole batch, then ``epochs`` passes
over it in ``minibatches`` shuffled minibatches, each one Adam step of the clipped surrogate, the
clipped value loss and the entropy bonus, with the gradient norm clipped. The losses are those of
Kostrikov's ``pytorch-a2c-ppo-acktr`` that facebookresearch/level-replay and dcd build on: the
value loss is ``value_coef * 1/2 (V - R)^2`` (TorchRL's ``l2`` with ``critic_coeff = value_coef / 2``).
The acting passes keep no graph: every minibatch is evaluated again at the current weights.
Where the rollout has a ``train_mask`` (a curriculum's: PLR⊥), the epochs use its steps only (the
advantages are still computed over the whole rollout); none: no step, and NaN losses (as A2C's);
fewer than ``minibatches``: one minibatch per step. A single step's advantage is not normalised
(it has no spread); a config whose whole batch has fewer steps than ``minibatches`` is refused.
Its checkpoint holds the Adam state.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import torch
from tensordict import TensorDictBase
from tensordict.nn import TensorDictModule
from torch import nn
from torchrl.modules import ProbabilisticActor
from torchrl.objectives import ClipPPOLoss
from torchrl.objectives.value import GAE

from gvgai_pcg.config_rules import ConfigError, Flag, Integer, Number
from gvgai_pcg.curricula.signals import TRAIN_MASK
from gvgai_pcg.rl.learners.base import Learner, Update, UpdateCheck
from gvgai_pcg.rl.learners.spec import LearnerSpec


class PPO(Learner):
    keep_acting_graph = False  # the update evaluates every minibatch at the current weights

    def __init__(self, algo: Mapping[str, Any], net: nn.Module, actor_critic: TensorDictModule) -> None:
        super().__init__(algo, net, actor_critic)
        obs_key = actor_critic.in_keys[0]
        # one network, read twice: its logits as the actor's, its value as the critic's
        actor = ProbabilisticActor(
            TensorDictModule(net, in_keys=[obs_key], out_keys=["logits", "actor_value"]),
            in_keys=["logits"],
            out_keys=["action"],
            distribution_class=torch.distributions.Categorical,
            distribution_kwargs={"validate_args": False},
        )
        critic = TensorDictModule(net, in_keys=[obs_key], out_keys=["critic_logits", "state_value"])
        self.value_coef = float(algo["value_coef"])
        self.loss_module = ClipPPOLoss(
            actor,
            critic,
            clip_epsilon=float(algo["clip_epsilon"]),
            entropy_bonus=float(algo["entropy_coef"]) > 0,
            entropy_coeff=float(algo["entropy_coef"]),
            critic_coeff=self.value_coef / 2,  # 1/2 (V - R)^2, as the reference implementations
            loss_critic_type="l2",
            normalize_advantage=False,  # normalised over the whole batch below
            clip_value=bool(algo["clip_value"]),
        )
        self.log_prob_key = self.loss_module.tensor_keys.sample_log_prob
        self.advantage_module = GAE(
            gamma=float(algo["gamma"]),
            lmbda=float(algo["gae_lambda"]),
            value_network=critic,
            deactivate_vmap=True,  # the network takes any leading dims itself
        )
        self.optimizer = torch.optim.Adam(net.parameters(), lr=float(algo["lr"]), eps=float(algo["adam_eps"]))
        self.epochs, self.minibatches = int(algo["epochs"]), int(algo["minibatches"])
        self.max_grad_norm = float(algo["max_grad_norm"])
        self.normalize_advantage = bool(algo["normalize_advantage"])

    def update(self, rollout: TensorDictBase, check: UpdateCheck) -> Update:
        batch = rollout.exclude("logits", "state_value").copy()
        with torch.no_grad():
            log_probs = rollout.get("logits").log_softmax(-1)
            batch.set(
                self.log_prob_key, log_probs.gather(-1, rollout.get("action").unsqueeze(-1)).squeeze(-1)
            )
            self.advantage_module(batch)  # advantage, value_target, state_value [B, T, 1]
        signals = {key: batch.get(key).squeeze(-1) for key in ("advantage", "value_target", "state_value")}
        flat = batch.reshape(-1)
        mask = rollout.get(TRAIN_MASK, None)
        if mask is not None:  # a curriculum's: only these steps train (PLR⊥)
            flat = flat[mask.reshape(-1)]
            if flat.shape[0] == 0:  # no replayed step: no step, and no losses to log
                return Update.untrained(signals)
        if self.normalize_advantage and flat.shape[0] > 1:  # one step has no spread to divide by
            advantage = flat.get("advantage")
            flat.set("advantage", (advantage - advantage.mean()) / (advantage.std() + 1e-5))
        sums = torch.zeros(3)
        steps = 0
        for _ in range(self.epochs):
            for indices in torch.randperm(flat.shape[0]).chunk(self.minibatches):
                losses = self.loss_module(flat[indices])
                loss = losses["loss_objective"] + losses["loss_critic"] + losses.get("loss_entropy", 0.0)
                self.optimizer.zero_grad(set_to_none=True)
                loss.backward()
                grad_norm = torch.nn.utils.clip_grad_norm_(self.net.parameters(), self.max_grad_norm)
                check(loss, grad_norm)  # before it is applied
                self.optimizer.step()
                value_loss = losses["loss_critic"].detach() / max(self.value_coef, 1e-12)
                entropy = losses.get("entropy", torch.zeros(())).detach()
                sums += torch.stack([losses["loss_objective"].detach(), value_loss, entropy]).float()
                steps += 1
        policy_loss, value_loss, entropy = sums / steps
        return Update(policy_loss, value_loss, entropy, signals)

    def state_dict(self) -> dict[str, Any]:
        return self.optimizer.state_dict()

    def load_state_dict(self, state: dict[str, Any]) -> None:
        self.optimizer.load_state_dict(state)


def check_batch(algo: Mapping[str, Any], config: Mapping[str, Any]) -> None:
    """Every minibatch needs a step: ``torch.chunk`` would silently make fewer of them."""
    steps = int(config["env"]["num_envs"]) * int(algo["n_steps"]) * int(config["collector"]["workers"])
    if int(algo["minibatches"]) > steps:
        counted = f"{steps} step{'s' if steps != 1 else ''}"
        raise ConfigError(
            f"algo.minibatches={algo['minibatches']}: expected at most the {counted} of a batch "
            "(env.num_envs x algo.n_steps x collector.workers); lower it, or raise algo.n_steps"
        )


SPEC = LearnerSpec(
    name="ppo",
    learner=PPO,
    schema={
        "n_steps": Integer(1),
        "gamma": Number(0.0, 1.0),
        "gae_lambda": Number(0.0, 1.0),
        "lr": Number(0.0, low_open=True),
        "adam_eps": Number(0.0, low_open=True),
        "epochs": Integer(1),
        "minibatches": Integer(1),
        "clip_epsilon": Number(0.0, low_open=True),
        "clip_value": Flag(),
        "entropy_coef": Number(0.0),
        "value_coef": Number(0.0),
        "max_grad_norm": Number(0.0, low_open=True),
        "normalize_advantage": Flag(),
    },
    description="PPO (TorchRL's ClipPPOLoss and GAE), the UED libraries' Procgen defaults",
    check=check_batch,
)
