"""The uniformly random agent of the study's tables: every action of the Gym set, NIL included,
with equal probability, from its own seeded generator."""

from __future__ import annotations

import torch
from tensordict import TensorDictBase


class RandomAgent:
    """A policy that ignores its observation and samples ``num_actions`` uniformly."""

    def __init__(self, num_actions: int, seed: int = 0, device: torch.device | str = "cpu") -> None:
        self.num_actions = num_actions
        self.generator = torch.Generator(device=device).manual_seed(seed)
        self.device = torch.device(device)

    def __call__(self, tensordict: TensorDictBase) -> torch.Tensor:
        batch = tensordict.batch_size[0]
        return torch.randint(0, self.num_actions, (batch,), generator=self.generator, device=self.device)
