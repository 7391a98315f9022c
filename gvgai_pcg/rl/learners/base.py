"""The interface between the shared training loop (``gvgai_pcg.rl.training``) and a learner.

The loop owns everything around an update: the env and its collector, the network, the log,
checkpoints, snapshots, signals and the divergence guard. A learner owns the update: its loss
module, its optimizer, the rollout length it needs, and what its checkpoint holds (its
``state_dict`` is saved as the checkpoint's ``optimizer`` entry, and ``load_state_dict`` gets it
back on resume).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import torch
from tensordict import TensorDictBase
from tensordict.nn import TensorDictModule
from torch import nn

# check(loss, grad_norm): the loop's divergence guard, called by the learner before every
# optimizer step (it raises DivergenceError when either is not finite)
UpdateCheck = Callable[[torch.Tensor, torch.Tensor], None]


@dataclass
class Update:
    """What one update reports.

    Args:
        policy_loss, value_loss, entropy: detached 0-d tensors (means over the update), logged;
            NaN where the update trained on no step (a curriculum's ``train_mask`` without one:
            PLR⊥'s batch without a replayed level), so the log leaves that update out of its means
            (``update_log.mean_losses``) instead of counting zeros.
        signals: per-step learning signals of the rollout ``[B, T]`` (``advantage``,
            ``value_target``, ``state_value``), detached, for a curriculum's ``observe``; ``None``
            when the learner has none.
    """

    policy_loss: torch.Tensor
    value_loss: torch.Tensor
    entropy: torch.Tensor
    signals: Mapping[str, torch.Tensor] | None = None

    def stacked(self) -> torch.Tensor:
        """``[policy_loss, value_loss, entropy]`` in one tensor (one host read per log row)."""
        return torch.stack([self.policy_loss, self.value_loss, self.entropy])

    @classmethod
    def untrained(cls, signals: Mapping[str, torch.Tensor] | None = None) -> Update:
        """An update that trained on no step: NaN losses (nothing was learnt), the signals still."""
        nan = torch.tensor(float("nan"))
        return cls(nan, nan.clone(), nan.clone(), signals)


class Learner:
    """Base class of learners: built once per run from its ``algo`` config.

    Args:
        algo: the ``algo`` config section (already checked against the spec's schema).
        net: the actor-critic network (``obs -> logits [B, A], value [B, 1]``).
        actor_critic: ``net`` as a ``TensorDictModule`` (observation -> ``logits``, ``state_value``).
    """

    def __init__(self, algo: Mapping[str, Any], net: nn.Module, actor_critic: TensorDictModule) -> None:
        self.algo, self.net, self.actor_critic = algo, net, actor_critic

    @property
    def n_steps(self) -> int:
        """Steps of every env in one rollout."""
        return int(self.algo["n_steps"])

    #: whether ``ActingRollouts`` keeps the acting passes' graph (``None``: its default by batch
    #: size). Only a learner whose first gradient is taken at the acting weights can use it.
    keep_acting_graph: bool | None = False

    def update(self, rollout: TensorDictBase, check: UpdateCheck) -> Update:
        """Learn from ``rollout [B, T]``; call ``check(loss, grad_norm)`` before each optimizer step.
        Where the rollout has a ``train_mask`` (``[B, T]`` bool, from the curriculum), take
        gradients from its steps only, and no step where it has none."""
        raise NotImplementedError

    def state_dict(self) -> dict[str, Any]:
        """What the checkpoint keeps of the learner (its optimizer's state, at least)."""
        raise NotImplementedError

    def load_state_dict(self, state: dict[str, Any]) -> None:
        raise NotImplementedError
