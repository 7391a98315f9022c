"""Actor-critic networks: one shared torso, a policy head (logits) and a value head.

``nature`` is the study's network (baselines' Nature CNN on the raw screen, GENERATORS.md §3);
``compact`` is a small CNN on the ``tiles`` observation (one channel per sprite type, one cell
per tile), the fast default. Both take uint8 observations ``[N, C, H, W]`` and return
``logits [N, A]`` and ``state_value [N, 1]``; initialisation is orthogonal as in baselines
(gain sqrt(2) in the torso, 0.01 for the policy head, 1 for the value head).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import torch
from tensordict.nn import TensorDictModule
from torch import nn

if TYPE_CHECKING:
    from omegaconf import DictConfig
    from torchrl.envs import EnvBase

MODELS = ("nature", "compact")
CHANNELS_LAST_TORSOS = {"compact": torch.channels_last}


def orthogonal_(layer: nn.Module, gain: float) -> nn.Module:
    """Orthogonal weights with ``gain`` and zero biases (baselines' ``ortho_init``)."""
    nn.init.orthogonal_(layer.weight, gain)
    nn.init.zeros_(layer.bias)
    return layer


def nature_torso(channels: int) -> nn.Sequential:
    """Conv 32-8x8/4, 64-4x4/2, 64-3x3/1 (VALID padding, ReLU), flattened."""
    g = math.sqrt(2)
    return nn.Sequential(
        orthogonal_(nn.Conv2d(channels, 32, 8, stride=4), g),
        nn.ReLU(),
        orthogonal_(nn.Conv2d(32, 64, 4, stride=2), g),
        nn.ReLU(),
        orthogonal_(nn.Conv2d(64, 64, 3, stride=1), g),
        nn.ReLU(),
        nn.Flatten(),
    )


def compact_torso(channels: int) -> nn.Sequential:
    """Conv 16-3x3/1 and 32-3x3/2 (padding 1, ReLU) on the tile grid, flattened: about 0.6M
    multiply-adds per Zelda observation, so a CPU trains it faster than the env steps."""
    g = math.sqrt(2)
    return nn.Sequential(
        orthogonal_(nn.Conv2d(channels, 16, 3, padding=1), g),
        nn.ReLU(),
        orthogonal_(nn.Conv2d(16, 32, 3, stride=2, padding=1), g),
        nn.ReLU(),
        nn.Flatten(),
    )


class ActorCritic(nn.Module):
    """A conv torso, an FC layer and two heads; the observation is cast to float and scaled.

    Args:
        torso: ``"nature"`` or ``"compact"``.
        obs_shape: ``(C, H, W)`` of one observation.
        num_actions: the size of the discrete action set.
        hidden: width of the FC layer after the torso (512 in the study).
        scale: what the uint8 observation is divided by (255 for pixels, 1 for tiles).
    """

    def __init__(
        self, torso: str, obs_shape: tuple[int, int, int], num_actions: int, hidden: int, scale: float
    ) -> None:
        super().__init__()
        builders = {"nature": nature_torso, "compact": compact_torso}
        if torso not in builders:
            raise ValueError(f"unknown model {torso!r}; valid models are: {', '.join(MODELS)}")
        conv = builders[torso](obs_shape[0])
        with torch.no_grad():
            flat = conv(torch.zeros(1, *obs_shape)).shape[-1]
        self.torso = nn.Sequential(conv, orthogonal_(nn.Linear(flat, hidden), math.sqrt(2)), nn.ReLU())
        self.policy_head = orthogonal_(nn.Linear(hidden, num_actions), 0.01)
        self.value_head = orthogonal_(nn.Linear(hidden, 1), 1.0)
        self.scale = float(scale)
        # Layout only, the same numbers up to rounding: oneDNN's convolutions on the CPU run the
        # compact torso's small grids faster channels-last (training 4-10 % more frames/s), the
        # Nature CNN's large screens slower (docs/benchmarks.md, "The network's memory layout").
        self.memory_format = CHANNELS_LAST_TORSOS.get(torso, torch.contiguous_format)
        self.to(memory_format=self.memory_format)

    def forward(self, obs: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """``obs [*, C, H, W]`` uint8 -> ``logits [*, A]``, ``state_value [*, 1]``."""
        batch = obs.shape[:-3]
        x = obs.reshape(-1, *obs.shape[-3:]).to(torch.float32, memory_format=self.memory_format)
        if self.scale != 1.0:
            x = x / self.scale
        h = self.torso(x)
        logits, value = self.policy_head(h), self.value_head(h)
        return logits.reshape(*batch, -1), value.reshape(*batch, 1)


def make_actor_critic(
    name: str, obs_kind: str, obs_shape: tuple[int, int, int], num_actions: int, hidden: int
) -> ActorCritic:
    """The network ``name`` for observations of kind ``obs_kind`` (pixels are scaled by 1/255)."""
    return ActorCritic(name, obs_shape, num_actions, hidden, scale=255.0 if obs_kind == "pixels" else 1.0)


def actor_critic_for(env: EnvBase, model: DictConfig, obs_key: str) -> ActorCritic:
    """The network of the ``model`` config (``name``, ``hidden``) for ``env``'s observations at
    ``obs_key`` and its actions: what training and the benchmarks build alike."""
    shape = tuple(env.observation_spec[obs_key].shape[-3:])
    return make_actor_critic(model.name, obs_key, shape, env.action_spec.space.n, int(model.hidden))


def as_tensordict_module(net: nn.Module, obs_key: str) -> TensorDictModule:
    """``net`` reading ``obs_key`` and writing ``"logits"`` and ``"state_value"`` (the entries the
    A2C loss and the acting policy use)."""
    return TensorDictModule(net, in_keys=[obs_key], out_keys=["logits", "state_value"])
