"""The study's A2C loss (OpenAI Baselines semantics) as a TorchRL ``LossModule``.

What it keeps true (GENERATORS.md §3):

- n-step returns are bootstrapped from the value of the observation after the rollout and cut
  at episode ends: a real end (``terminated``) contributes no value, a step-limit end
  (``truncated``) bootstraps from the value of its final observation;
- advantages are ``R - V`` (no normalisation, no GAE);
- policy loss ``mean(A * -log pi(a|s))``, value loss ``mean(1/2 (V - R)^2)``, and the total
  ``pg - entropy_coef * entropy + value_coef * value_loss`` is the sum of the three
  ``loss_*`` entries of the output;
- where the rollout has a ``train_mask`` (``[B, T]`` bool, a curriculum's: PLR⊥), the three means
  are over its steps only (the returns and advantages still use every step).
"""

from __future__ import annotations

import torch
from tensordict import TensorDict, TensorDictBase
from tensordict.nn import TensorDictModule
from torchrl.objectives import LossModule

from gvgai_pcg.curricula.signals import TRAIN_MASK


def nstep_returns(
    rewards: torch.Tensor,
    bootstrap: torch.Tensor,
    terminated: torch.Tensor,
    done: torch.Tensor,
    gamma: float,
) -> torch.Tensor:
    """Discounted returns of a rollout, cut at episode ends.

    Args:
        rewards: ``[B, T]`` reward of each step.
        bootstrap: ``[B, T]`` value of the observation after each step, read only where the
            episode ended (``done``) or at the last step ``T - 1``.
        terminated: ``[B, T]`` bool, the episode really ended at this step (no bootstrap).
        done: ``[B, T]`` bool, the episode ended at this step (terminated or truncated).
        gamma: the discount.

    Returns:
        ``[B, T]``: ``R_t = r_t + gamma * (1 - terminated_t) * (R_{t+1} if the episode goes on,
        else the bootstrap value)``.
    """
    returns = torch.empty_like(rewards)
    later = bootstrap[:, -1]
    for t in reversed(range(rewards.shape[1])):
        following = torch.where(done[:, t], bootstrap[:, t], later)
        later = rewards[:, t] + gamma * (~terminated[:, t]).to(rewards.dtype) * following
        returns[:, t] = later
    return returns


def _mean_over(mask: torch.Tensor | None):
    """The mean of a ``[B, T]`` tensor over every step (``mask`` ``None``: ``Tensor.mean``, as it
    always was), or over the steps of ``mask`` only (a curriculum's ``train_mask``; 0 where none)."""
    if mask is None:
        return torch.Tensor.mean
    mask = mask.reshape(mask.shape[:2])
    weights, count = mask.to(torch.float32), mask.sum().clamp(min=1)
    return lambda values: (values * weights.to(values.dtype)).sum() / count


class A2CLoss(LossModule):
    """A2C on a rollout tensordict ``[B, T]`` from a ``Collector``.

    Args:
        actor_critic: a ``TensorDictModule`` reading the observation and writing ``"logits"``
            ``[.., A]`` and ``"state_value"`` ``[.., 1]`` (one shared torso).
        gamma: the discount (0.99).
        entropy_coef: weight of the entropy bonus (0.01).
        value_coef: weight of the value loss (0.5).

    The output holds ``loss_objective`` (policy), ``loss_critic`` (weighted value loss),
    ``loss_entropy`` (``-entropy_coef * entropy``) and, detached for logging, ``entropy``,
    ``value_loss`` (unweighted) and ``returns_mean``; and, detached, the per-step ``[B, T]``
    ``advantage`` (``R - V``), ``value_target`` (``R``) and ``state_value`` (``V``).
    """

    def __init__(
        self,
        actor_critic: TensorDictModule,
        gamma: float = 0.99,
        entropy_coef: float = 0.01,
        value_coef: float = 0.5,
    ) -> None:
        super().__init__()
        self.actor_critic = actor_critic
        self.obs_key = actor_critic.in_keys[0]
        # A plain TensorDictModule (obs -> logits, state_value) is called as its network.
        plain = type(actor_critic) is TensorDictModule and list(actor_critic.out_keys) == [
            "logits",
            "state_value",
        ]
        net = actor_critic.module if plain and len(actor_critic.in_keys) == 1 else None
        object.__setattr__(self, "_net", net)  # not registered a second time (its state_dict keys)
        self.gamma, self.entropy_coef, self.value_coef = float(gamma), float(entropy_coef), float(value_coef)

    def _evaluate(self, obs: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        if self._net is not None:  # the plain network, without a tensordict round trip
            logits, values = self._net(obs)
            return logits, values.squeeze(-1)
        out = self.actor_critic(TensorDict({self.obs_key: obs}, batch_size=obs.shape[:1]))
        return out.get("logits"), out.get("state_value").squeeze(-1)

    @torch.no_grad()
    def bootstrap_values(self, rollout: TensorDictBase, values: torch.Tensor) -> torch.Tensor:
        """``[B, T]`` value after each step: the next step's value inside an episode, the value of
        the final observation where an episode was truncated and at the end of the rollout."""
        next_obs = rollout.get(("next", self.obs_key))
        bootstrap = torch.zeros_like(values)
        bootstrap[:, :-1] = values[:, 1:]
        bootstrap[:, -1] = self._evaluate(next_obs[:, -1])[1]
        truncated = rollout.get(("next", "truncated")).squeeze(-1).clone()
        truncated[:, -1] = False
        if truncated.any():
            bootstrap[truncated] = self._evaluate(next_obs[truncated])[1]
        return bootstrap

    def policy_outputs(self, rollout: TensorDictBase) -> tuple[torch.Tensor, torch.Tensor]:
        """``logits [B, T, A]`` and ``values [B, T]`` of the rollout's observations, with their
        graph: the acting passes' own when they kept it (``ActingRollouts``; the weights have not
        changed since), else a forward pass over every frame."""
        logits, values = rollout.get("logits", None), rollout.get("state_value", None)
        if logits is not None and values is not None and logits.requires_grad and values.requires_grad:
            return logits, values.squeeze(-1)
        b, t = rollout.batch_size
        obs = rollout.get(self.obs_key)
        logits, values = self._evaluate(obs.reshape(b * t, *obs.shape[2:]))
        return logits.reshape(b, t, -1), values.reshape(b, t)

    def forward(self, rollout: TensorDictBase) -> TensorDict:
        """``rollout [B, T]`` with the observation, ``action``, and ``("next", reward | done |
        terminated | truncated | <observation>)``; ``logits`` and ``state_value`` that carry
        their autograd graph are used as they are."""
        logits, values = self.policy_outputs(rollout)
        with torch.no_grad():
            returns = nstep_returns(
                rollout.get(("next", "reward")).squeeze(-1),
                self.bootstrap_values(rollout, values.detach()),
                rollout.get(("next", "terminated")).squeeze(-1),
                rollout.get(("next", "done")).squeeze(-1),
                self.gamma,
            )
        advantages = returns - values.detach()
        mean = _mean_over(rollout.get(TRAIN_MASK, None))
        # The categorical policy's log-probabilities and entropy, without a distribution object
        # (its argument handling cost more than these ops at the study's 12 envs).
        log_probs = logits.log_softmax(-1)
        log_prob = log_probs.gather(-1, rollout.get("action").unsqueeze(-1)).squeeze(-1)
        entropy = mean(-(log_probs.exp() * log_probs).sum(-1))
        value_loss = 0.5 * mean((values - returns).pow(2))
        return TensorDict(
            {
                "loss_objective": mean(advantages * -log_prob),
                "loss_critic": self.value_coef * value_loss,
                "loss_entropy": -self.entropy_coef * entropy,
                "entropy": entropy.detach(),
                "value_loss": value_loss.detach(),
                "returns_mean": returns.mean(),
                # per step [B, T], for a curriculum's scores (PLR's value loss, GAE)
                "advantage": advantages,
                "value_target": returns,
                "state_value": values.detach(),
            },
            batch_size=[],
        )
