"""Next episodes prepared ahead, in bulk, for level sources that allow it.

A partial reset of a few envs costs the reset tick of a small batch: a few hundred small ops
whatever the number of envs (on the CPU, a sizeable part of a B = 4096 step). When the next
level of every env is known in advance (its source does not look at anything that changes during
training, ``prepare_ahead`` on the source), the env instead prepares the next episode of every
env whose episode is not ready, all in one batch, and a reset takes its envs' rows from here.
Each row is exactly what the reset would have computed (same level, episode seed and reset tick),
so the results do not change; only the reset tick's cost is shared by many resets. The price is
one more game state per env (not its observation: a reset renders its few envs itself).
"""

from __future__ import annotations

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.rows import select_rows
from gvgai_pcg.envs.states import merge_states
from gvgai_pcg.levels import Level


class ReadyEpisodes:
    """One prepared next episode per env (its state after the reset tick, and its level)."""

    def __init__(self, num_envs: int) -> None:
        self.state: TensorDict | None = None
        self.levels: list[Level | None] = [None] * num_envs
        # The episode number each row was prepared for (-1: none); a row counts only while it
        # equals its env's next episode number.
        self.episode = torch.full((num_envs,), -1, dtype=torch.int64)

    def missing(self, next_episode: torch.Tensor) -> torch.Tensor:
        """The envs (sorted CPU indices) whose next episode is not prepared."""
        return (self.episode != next_episode).nonzero().flatten()

    def store(
        self, index: torch.Tensor, states: TensorDict, levels: list[Level], episode: torch.Tensor
    ) -> None:
        """Keep ``states`` (after their reset tick) as the next episodes of envs ``index``."""
        if self.state is None:
            if len(index) != len(self.levels):
                raise ValueError("the first episodes prepared must cover every env")
            self.state = states
        else:
            self.state = merge_states(self.state, states, index.to(self.state.device))
        for i, level in zip(index.tolist(), levels, strict=True):
            self.levels[i] = level
        self.episode[index] = episode

    def take(self, index: torch.Tensor) -> tuple[TensorDict, list[Level]]:
        """The prepared episodes of envs ``index`` (all ready), which are then used up."""
        if self.state is None or (self.episode[index] < 0).any():
            raise RuntimeError("an episode was taken before it was prepared")
        states = select_rows(self.state, index.to(self.state.device))
        self.episode[index] = -1
        return states, [self.levels[i] for i in index.tolist()]

    def clear(self) -> None:
        """Forget every prepared episode (the env seeds changed)."""
        self.episode.fill_(-1)
