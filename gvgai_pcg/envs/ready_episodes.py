"""Next episodes prepared ahead, in bulk, for level sources that allow it.

A partial reset of a few envs costs the reset tick of a small batch: a few hundred small ops
whatever the number of envs (on the CPU, a sizeable part of a B = 4096 step). When the next levels
of every env are known in advance (its source does not look at anything that changes during
training, ``prepare_ahead`` on the source), the env instead prepares the next ``depth`` episodes of
every env whose episodes are not ready, all in one batch, and a reset takes its envs' rows from
here. A source whose levels also depend on the difficulty (generated levels) is prepared at each
env's difficulty of the moment, and a row counts only for that difficulty. Each row is exactly what
the reset would have computed (same level, episode seed and reset tick), so the results do not
change; only the reset tick's cost is shared by many resets. One episode ahead is not enough where
episodes are short: in Frogs under random play an env often ends its next episode within a few
steps, and with one episode ahead nearly every step prepared the one or two envs it had just used
(a whole reset tick, and a store, for each). The price is ``depth`` more game states per env and,
where the env keeps them (observations of a few tens of MB at most), as many observations: drawing
a reset's one or two envs costs a render's ~50 small ops (0.2-0.3 ms, a quarter of a step of 64
Zelda envs), where taking its rows costs one.
"""

from __future__ import annotations

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.rows import copy_tensor_rows_, select_rows
from gvgai_pcg.envs.states import bucket_entity_tables, entity_capacities, merge_states, pad_entity_tables
from gvgai_pcg.levels import Level


class ReadyEpisodes:
    """The next ``depth`` prepared episodes of each of ``num_envs`` envs (each one's state after
    the reset tick, its level and, if ``keeps_observations``, its first observation). Episode
    ``e`` of env ``i`` lives in row ``(e % depth) * num_envs + i``."""

    def __init__(self, num_envs: int, keeps_observations: bool = False, depth: int = 1) -> None:
        if depth < 1:
            raise ValueError(f"depth must be at least 1, got {depth}")
        self.num_envs, self.depth = num_envs, depth
        self.keeps_observations = keeps_observations
        self.state: TensorDict | None = None
        self.observations: torch.Tensor | None = None
        self.levels: list[Level | None] = [None] * (depth * num_envs)
        # The episode number each row was prepared for (-1: none); a row counts only while it
        # holds the episode asked for (and, where difficulties are given, at the difficulty asked).
        self.episode = torch.full((depth * num_envs,), -1, dtype=torch.int64)
        self.difficulty = torch.full((depth * num_envs,), float("nan"), dtype=torch.float64)

    def rows(self, envs: torch.Tensor, episodes: torch.Tensor) -> torch.Tensor:
        """The rows (CPU) of episodes ``episodes`` of envs ``envs``."""
        return episodes % self.depth * self.num_envs + envs

    def ready(
        self, envs: torch.Tensor, episodes: torch.Tensor, difficulties: torch.Tensor | None = None
    ) -> bool:
        """Whether episode ``episodes[k]`` of env ``envs[k]`` is prepared, for every ``k`` (and at
        ``difficulties[envs[k]]``, where every env's difficulty is given)."""
        rows = self.rows(envs, episodes)
        prepared = self.episode[rows] == episodes
        if difficulties is not None:
            prepared &= self.difficulty[rows] == difficulties[envs]
        return bool(prepared.all())

    def missing(
        self, next_episode: torch.Tensor, difficulties: torch.Tensor | None = None
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """The envs and episode numbers (CPU, in row order) of the episodes not prepared among
        every env's next ``depth`` (env ``i``'s from ``next_episode[i]`` on; at difficulty
        ``difficulties[i]``, where given)."""
        envs = torch.arange(self.num_envs).repeat(self.depth)
        slot = torch.arange(self.depth).repeat_interleave(self.num_envs)
        # Row (slot, i) holds the first of env i's next depth episodes that is slot mod depth.
        base = next_episode.repeat(self.depth)
        episodes = base + (slot - base) % self.depth
        missing = self.episode != episodes
        if difficulties is not None:
            missing |= self.difficulty != difficulties[envs]
        missing = missing.nonzero().flatten()
        return envs[missing], episodes[missing]

    def store(
        self,
        envs: torch.Tensor,
        episodes: torch.Tensor,
        states: TensorDict,
        levels: list[Level],
        observations: torch.Tensor | None = None,
        round_up: bool = False,
        difficulties: torch.Tensor | None = None,
    ) -> None:
        """Keep ``states`` (after their reset tick) and, if kept, their ``observations`` as
        episodes ``episodes`` of envs ``envs`` (prepared at ``difficulties``, one per row, where
        the levels depend on it); entity tables grow as ``merge_states``'s ``round_up`` says."""
        if self.keeps_observations and observations is None:
            raise ValueError("this store keeps observations, and none were given")
        rows = self.rows(envs, episodes)
        if self.state is None and not torch.equal(rows, torch.arange(len(self.episode))):
            # A first store of some rows (a bounded bulk): every row starts as a copy of the
            # first one given, never taken (its episode is -1), and the given rows go in below.
            filler = torch.zeros(len(self.episode), dtype=torch.int64, device=states.device)
            self.state = select_rows(bucket_entity_tables(states) if round_up else states, filler)
            self.observations = observations.index_select(0, filler) if self.keeps_observations else None
        if self.state is None:
            self.state = bucket_entity_tables(states) if round_up else states
            # Rows are later copied into it in place, so it must be ours alone.
            self.observations = observations.clone() if self.keeps_observations else None
        else:
            device_rows = rows.to(self.state.device)
            self.state = merge_states(self.state, states, device_rows, round_up=round_up)
            if self.keeps_observations:
                copy_tensor_rows_(self.observations, device_rows, observations)
        for row, level in zip(rows.tolist(), levels, strict=True):
            self.levels[row] = level
        self.episode[rows] = episodes
        self.difficulty[rows] = float("nan") if difficulties is None else difficulties.to(torch.float64)

    def take_into(
        self, state: TensorDict, envs: torch.Tensor, episodes: torch.Tensor, round_up: bool = False
    ) -> tuple[TensorDict, list[Level], torch.Tensor | None]:
        """Take episodes ``episodes`` of envs ``envs`` (all ready), which are then used up: the
        running ``state`` with those envs replaced by them (``merge_states``, whose ``round_up``
        this passes on, row by row from here: no state of their own is built first), their levels
        and their observations (None where they are not kept)."""
        rows = self.rows(envs, episodes)
        if self.state is None or not torch.equal(self.episode[rows], episodes):
            raise RuntimeError("an episode was taken before it was prepared")
        self.episode[rows] = -1
        self._widen_to(state)
        device_rows = rows.to(self.state.device)
        merged = merge_states(state, self.state, envs.to(self.state.device), round_up, device_rows)
        observations = self.observations.index_select(0, device_rows) if self.keeps_observations else None
        return merged, [self.levels[row] for row in rows.tolist()], observations

    def _widen_to(self, state: TensorDict) -> None:
        """Grow the prepared entity tables that are narrower than ``state``'s, once, so that
        taking rows does not grow each one on every take."""
        ours, running = entity_capacities(self.state), entity_capacities(state)
        narrower = {key: width for key, width in running.items() if width > ours.get(key, width)}
        if narrower:
            self.state = pad_entity_tables(self.state, narrower)

    def clear(self) -> None:
        """Forget every prepared episode (the env seeds changed)."""
        self.episode.fill_(-1)
        self.difficulty.fill_(float("nan"))
