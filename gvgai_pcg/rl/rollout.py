"""Rollouts of one natively batched env, with the acting passes kept for the update.

In A2C the network acts and learns with the same weights: the update follows the rollout, so
the logits and values of the acting passes are exactly what the update's forward pass would
compute again on the same observations. ``ActingRollouts`` keeps the acting passes' autograd
graph instead, and the loss (``A2CLoss``) reuses it: a batch costs the acting forward passes,
one backward and one bootstrap pass, not a second forward pass over every frame. It also
steps the env directly (no collector, no probabilistic actor, no per-step tensordict copies):
at the default 64 envs those cost as much as the update.

What it keeps true: the rollout tensordict has the layout of a TorchRL collector's
(``[B, T]``, the observation, ``action`` and ``("next", reward | done | terminated |
truncated | score | won | level_seed | level_difficulty | <observation>)``), actions are sampled
from the policy with the global torch generator, and every env of the batch restarts on its own
when its episode ends (``step_and_maybe_reset``), so transforms such as the ``DifficultyTransform``
see every step.

Keeping the graph pays only from about 24 envs (``KEEP_GRAPH_FROM_ENVS``): the backward pass then
runs once per acting pass, and at small batches ``n_steps`` small backward passes cost more than
one batched forward and backward over the whole rollout (one thread, CPU: 12 envs, compact net
8.4 against 7.5 ms a batch, Nature CNN 98.5 against 91.6 ms; 64 envs 20.7 against 28.5 ms;
docs/history/benchmarks-notebook.md). Below it the acting passes run without a graph and the loss
recomputes them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import torch
from tensordict import TensorDict, TensorDictBase
from torch import nn
from torchrl.envs import EnvBase

# the level each step was played on (gvgai_pcg.curricula.signals attributes rollouts to levels)
LEVEL_KEYS = ("level_seed", "level_difficulty")
NEXT_KEYS = ("reward", "done", "terminated", "truncated", "score", "won", *LEVEL_KEYS)
KEEP_GRAPH_FROM_ENVS = 24  # where keeping the acting graph and recomputing cost the same


def keeps_acting_graph(num_envs: int) -> bool:
    """Whether rollouts of ``num_envs`` envs should keep their acting passes' graph (see above)."""
    return num_envs >= KEEP_GRAPH_FROM_ENVS


def sample_actions(logits: torch.Tensor) -> torch.Tensor:
    """``[B]`` actions drawn from the categorical policy ``logits [B, A]``."""
    return torch.multinomial(logits.detach().softmax(-1), 1).squeeze(-1)


class ActingRollouts:
    """Rollouts of ``n_steps`` steps of ``env`` acted by ``net`` (``obs -> logits, value``).

    Each rollout holds ``logits [B, T, A]`` and ``state_value [B, T, 1]``, with their autograd
    graph when it keeps it: then the update must consume a rollout (or drop it) before the next
    one is collected.

    Args:
        env: a batched TorchRL env (batch ``[B]``), transforms included.
        net: the actor-critic network, taking observations ``[B, C, H, W]``.
        obs_key: the observation entry (``"tiles"`` or ``"pixels"``).
        n_steps: steps per rollout (T).
        keep_graph: keep the acting passes' graph (default: ``keeps_acting_graph`` of the
            env's batch); without it ``logits`` and ``state_value`` are plain tensors.
        fused: the fused step (``gvgai_pcg.rl.fused.FusedStep`` of this env and net): the acting
            pass, the sampling and the env's tick run as one call, and the env's step only
            outputs it and restarts the finished envs. The same rollouts.
    """

    def __init__(
        self,
        env: EnvBase,
        net: nn.Module,
        obs_key: str,
        n_steps: int,
        keep_graph: bool | None = None,
        fused: Callable[[torch.Tensor], tuple[torch.Tensor, torch.Tensor, torch.Tensor]] | None = None,
    ) -> None:
        if n_steps < 1:
            raise ValueError(f"n_steps must be at least 1, got {n_steps}")
        self.env, self.net, self.obs_key, self.n_steps = env, net, obs_key, int(n_steps)
        if keep_graph is None:
            keep_graph = keeps_acting_graph(env.batch_size.numel())
        self.keep_graph = bool(keep_graph)
        self.fused = fused
        self._current: TensorDictBase | None = None

    def collect(self) -> TensorDict:
        """The next rollout, ``[B, T]``."""
        if self._current is None:
            self._current = self.env.reset()
        current = self._current
        observations, actions, logits, values, nexts = [], [], [], [], []
        for _ in range(self.n_steps):
            obs = current.get(self.obs_key)
            with torch.set_grad_enabled(self.keep_graph and torch.is_grad_enabled()):
                if self.fused is not None:
                    step_logits, step_value, action = self.fused(obs)
                else:
                    step_logits, step_value = self.net(obs)
            if self.fused is None:
                action = sample_actions(step_logits)
            current.set("action", action)
            stepped, current = self.env.step_and_maybe_reset(current)
            observations.append(obs)
            actions.append(action)
            logits.append(step_logits)
            values.append(step_value)
            nexts.append(stepped.get("next"))
        self._current = current
        batch = self.env.batch_size
        following = {key: torch.stack([n.get(key) for n in nexts], 1) for key in NEXT_KEYS}
        following[self.obs_key] = torch.stack([n.get(self.obs_key) for n in nexts], 1)
        return TensorDict(
            {
                self.obs_key: torch.stack(observations, 1),
                "action": torch.stack(actions, 1),
                "logits": torch.stack(logits, 1),
                "state_value": torch.stack(values, 1),
                "next": TensorDict(following, batch_size=(*batch, self.n_steps)),
            },
            batch_size=(*batch, self.n_steps),
        )

    def __iter__(self) -> Iterator[TensorDict]:
        while True:
            yield self.collect()

    def shutdown(self) -> None:
        self.env.close()
