"""Next episodes prepared ahead, in bulk, for level sources that allow it.

A partial reset of a few envs costs the reset tick of a small batch: a few hundred small ops
whatever the number of envs (on the CPU, a sizeable part of a B = 4096 step). When the next
level of every env is known in advance (its source does not look at anything that changes during
training, ``prepare_ahead`` on the source), the env instead prepares the next episode of every
env whose episode is not ready, all in one batch, and a reset takes its envs' rows from here.
Each row is exactly what the reset would have computed (same level, episode seed and reset tick),
so the results do not change; only the reset tick's cost is shared by many resets. The price is
one more game state per env and, where the env keeps them (observations of a few tens of MB at
most), one more observation: drawing a reset's one or two envs costs a render's ~50 small ops
(0.2-0.3 ms, a quarter of a step of 64 Zelda envs), where taking its rows costs one.
"""

from __future__ import annotations

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.rows import copy_tensor_rows_
from gvgai_pcg.envs.states import merge_states
from gvgai_pcg.levels import Level


class ReadyEpisodes:
    """One prepared next episode per env (its state after the reset tick, its level and, if
    ``keeps_observations``, its first observation)."""

    def __init__(self, num_envs: int, keeps_observations: bool = False) -> None:
        self.keeps_observations = keeps_observations
        self.state: TensorDict | None = None
        self.observations: torch.Tensor | None = None
        self.levels: list[Level | None] = [None] * num_envs
        # The episode number each row was prepared for (-1: none); a row counts only while it
        # equals its env's next episode number.
        self.episode = torch.full((num_envs,), -1, dtype=torch.int64)

    def missing(self, next_episode: torch.Tensor) -> torch.Tensor:
        """The envs (sorted CPU indices) whose next episode is not prepared."""
        return (self.episode != next_episode).nonzero().flatten()

    def store(
        self,
        index: torch.Tensor,
        states: TensorDict,
        levels: list[Level],
        episode: torch.Tensor,
        observations: torch.Tensor | None = None,
    ) -> None:
        """Keep ``states`` (after their reset tick) and, if kept, their ``observations`` as the
        next episodes of envs ``index``."""
        if self.keeps_observations and observations is None:
            raise ValueError("this store keeps observations, and none were given")
        if self.state is None:
            if len(index) != len(self.levels):
                raise ValueError("the first episodes prepared must cover every env")
            self.state = states
            # Rows are later copied into it in place, so it must be ours alone.
            self.observations = observations.clone() if self.keeps_observations else None
        else:
            rows = index.to(self.state.device)
            self.state = merge_states(self.state, states, rows)
            if self.keeps_observations:
                copy_tensor_rows_(self.observations, rows, observations)
        for i, level in zip(index.tolist(), levels, strict=True):
            self.levels[i] = level
        self.episode[index] = episode

    def take_into(
        self, state: TensorDict, index: torch.Tensor, round_up: bool = False
    ) -> tuple[TensorDict, list[Level], torch.Tensor | None]:
        """Take the prepared episodes of envs ``index`` (all ready), which are then used up: the
        running ``state`` with those envs replaced by them (``merge_states``, whose ``round_up``
        this passes on, row by row from here: no state of their own is built first), their levels
        and their observations (None where they are not kept)."""
        rows = self._use(index)
        merged = merge_states(state, self.state, rows, round_up=round_up, fresh_rows=rows)
        return merged, [self.levels[i] for i in index.tolist()], self._observations(rows)

    def _use(self, index: torch.Tensor) -> torch.Tensor:
        """Mark the episodes of envs ``index`` used; their rows (on the state's device)."""
        if self.state is None or (self.episode[index] < 0).any():
            raise RuntimeError("an episode was taken before it was prepared")
        self.episode[index] = -1
        return index.to(self.state.device)

    def _observations(self, rows: torch.Tensor) -> torch.Tensor | None:
        return self.observations.index_select(0, rows) if self.keeps_observations else None

    def clear(self) -> None:
        """Forget every prepared episode (the env seeds changed)."""
        self.episode.fill_(-1)
