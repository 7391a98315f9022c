"""The uniformly random agent of the study's tables: every action of the Gym set, NIL included,
with equal probability: from the evaluation runner's per-env draws when they are given, else from
its own seeded generator."""

from __future__ import annotations

import torch
from tensordict import TensorDictBase

from gvgai_pcg.evaluation.runner import SAMPLE_KEY


class RandomAgent:
    """A policy that ignores its observation and samples ``num_actions`` uniformly."""

    def __init__(self, num_actions: int, seed: int = 0, device: torch.device | str = "cpu") -> None:
        self.num_actions = num_actions
        self.generator = torch.Generator(device=device).manual_seed(seed)
        self.device = torch.device(device)

    def __call__(self, tensordict: TensorDictBase) -> torch.Tensor:
        draws = tensordict.get(SAMPLE_KEY, None)
        if draws is not None:
            return (draws * self.num_actions).long().clamp_(max=self.num_actions - 1).to(self.device)
        batch = tensordict.batch_size[0]
        return torch.randint(0, self.num_actions, (batch,), generator=self.generator, device=self.device)
