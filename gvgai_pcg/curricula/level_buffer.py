"""The level buffer of PLR⊥ and ACCEL: a bounded table of levels with their scores, shared by
every env and collector worker of a run and kept in its checkpoints (a ``SharedState``).

A level is identified by (``level_d``, ``seed``), the generator's difficulty and seed (ACCEL's
edited levels: their parent's d and a seed of their own, ``EDITED_SEED_BASE`` and up); ACCEL
also keeps each level's characters (``content``). The replay distribution is that of Jiang et al.
(2021, "Prioritized Level Replay", eq. 1-2), as facebookresearch/dcd's
``level_replay/level_sampler.py`` computes it (``sample_weights`` and ``_score_transform``):

* score prioritisation by rank, the temperature applied as a power:
  ``P_S(i) ∝ h(S_i)^(1/β)`` with ``h(S_i) = 1 / rank(S_i)`` (rank 1: the highest score);
* staleness ``C_i = clock - last_sampled_i`` (levels handed out since level i last was),
  ``P_C(i) = C_i / Σ C_j`` (uniform where every C is 0);
* ``P(i) = (1 - ρ) P_S(i) + ρ P_C(i)`` over the valid entries only.

A new level joins a buffer that has room, else replaces the lowest-scored entry when its own
score is at least as high (dcd's ``_partial_update_seed_score_buffer``); a level already in the
buffer has its score replaced by its latest episode's.
"""

from __future__ import annotations

import math

import torch

from gvgai_pcg.curricula.state import SharedState

EDITED_SEED_BASE = 2**50  # ACCEL's edited levels: above the training (2**31) and test (2**40) seeds


def rank_weights(scores: torch.Tensor, temperature: float) -> torch.Tensor:
    """``h(S_i)^(1/temperature)`` with ``h = 1/rank`` (rank 1: the highest score; ties by
    position), normalised to sum to 1. ``scores`` is ``[N]``, N >= 1."""
    order = torch.argsort(scores.to(torch.float64), descending=True, stable=True)
    ranks = torch.empty(len(scores), dtype=torch.float64)
    ranks[order] = torch.arange(1, len(scores) + 1, dtype=torch.float64)
    weights = (1.0 / ranks) ** (1.0 / temperature)
    return weights / weights.sum()


def staleness_weights(staleness: torch.Tensor) -> torch.Tensor:
    """``C_i / Σ C_j`` (uniform where every staleness is 0). ``staleness`` is ``[N]``, N >= 1."""
    staleness = staleness.to(torch.float64).clamp(min=0.0)
    total = staleness.sum()
    if total <= 0:
        return torch.full_like(staleness, 1.0 / len(staleness))
    return staleness / total


class LevelBuffer(SharedState):
    """``capacity`` levels: ``seed`` int64, ``level_d`` float64, ``score`` float32, ``max_return``
    float32 (MaxMC's highest return), ``last_sampled`` int64 (the ``clock`` when last handed out),
    ``valid`` bool, and, with ``height`` and ``width``, ``content`` uint8 ``[capacity, H, W]``
    (character codes of the level's rows)."""

    def __init__(self, capacity: int, height: int = 0, width: int = 0) -> None:
        super().__init__()
        if capacity < 1:
            raise ValueError(f"a level buffer needs a capacity >= 1, got {capacity}")
        self.capacity = int(capacity)
        self.register_shared("seed", torch.full((capacity,), -1, dtype=torch.int64))
        self.register_shared("level_d", torch.zeros(capacity, dtype=torch.float64))
        self.register_shared("score", torch.zeros(capacity, dtype=torch.float32))
        self.register_shared("max_return", torch.zeros(capacity, dtype=torch.float32))
        self.register_shared("last_sampled", torch.zeros(capacity, dtype=torch.int64))
        self.register_shared("valid", torch.zeros(capacity, dtype=torch.bool))
        self.register_shared("clock", torch.zeros(1, dtype=torch.int64))  # levels handed out so far
        if height and width:
            self.register_shared("content", torch.zeros(capacity, height, width, dtype=torch.uint8))

    # --- reading ---
    @property
    def size(self) -> int:
        return int(self.valid.sum())

    @property
    def filled(self) -> float:
        """The fraction of the capacity in use."""
        return self.size / self.capacity

    @property
    def difficulty(self) -> float:
        """The mean d of the buffer's levels (NaN while empty): the training log's ``difficulty``."""
        if not bool(self.valid.any()):
            return math.nan
        return float(self.level_d[self.valid].mean())

    def find(self, seeds: torch.Tensor, difficulties: torch.Tensor) -> torch.Tensor:
        """``[N]`` buffer index of each level (``seeds`` int64, ``difficulties`` float64), -1 where
        it is not in the buffer."""
        seeds, difficulties = seeds.reshape(-1, 1), difficulties.to(torch.float64).reshape(-1, 1)
        match = (self.seed == seeds) & (self.level_d == difficulties) & self.valid
        found = match.any(1)
        return torch.where(found, match.to(torch.int64).argmax(1), -1)

    def replay_probabilities(self, temperature: float, staleness_coef: float) -> torch.Tensor:
        """``[capacity]`` replay probabilities (0 for empty slots); the buffer must not be empty."""
        valid = self.valid.nonzero().flatten()
        if len(valid) == 0:
            raise ValueError("no level to replay: the level buffer is empty")
        by_score = rank_weights(self.score[valid], temperature)
        by_staleness = staleness_weights(self.clock[0] - self.last_sampled[valid])
        probabilities = torch.zeros(self.capacity, dtype=torch.float64)
        probabilities[valid] = (1.0 - staleness_coef) * by_score + staleness_coef * by_staleness
        return probabilities

    # --- moving (inside ``with self.lock:``) ---
    def tick(self) -> int:
        """Count one level handed out; returns the new clock."""
        self.clock.add_(1)
        return int(self.clock[0])

    def pick(self, probabilities: torch.Tensor, uniform: float) -> int:
        """The entry at quantile ``uniform`` (in [0, 1)) of ``probabilities``, marked as sampled now."""
        cumulative = probabilities.cumsum(0)
        index = int(torch.searchsorted(cumulative, uniform * float(cumulative[-1]), right=True))
        index = min(index, self.capacity - 1)
        while not bool(self.valid[index]):  # rounding past the last valid entry
            index -= 1
        self.last_sampled[index] = self.clock[0]
        return index

    def update(self, index: int, score: float, episode_return: float) -> None:
        """A replayed level's latest score (and its highest return so far)."""
        self.score[index] = score
        self.max_return[index] = max(float(self.max_return[index]), episode_return)

    def admits(self, score: float) -> bool:
        """Whether a new level of ``score`` would be kept (``insert``)."""
        return not bool(self.valid.all()) or score >= float(self.score.min())

    def insert(
        self,
        seed: int,
        difficulty: float,
        score: float,
        episode_return: float,
        content: torch.Tensor | None = None,
    ) -> int:
        """Add a new level: into a free slot, else in place of the lowest-scored level when its
        ``score`` is at least as high. Returns its index, or -1 where it was not kept."""
        if not self.admits(score):
            return -1
        free = (~self.valid).nonzero().flatten()
        index = int(free[0]) if len(free) > 0 else int(torch.argmin(self.score))
        return self.write(index, seed, difficulty, score, episode_return, content)

    def write(
        self,
        index: int,
        seed: int,
        difficulty: float,
        score: float,
        episode_return: float,
        content: torch.Tensor | None = None,
    ) -> int:
        """Put a new level in slot ``index`` (whatever held it is gone); returns ``index``."""
        self.seed[index], self.level_d[index], self.score[index] = seed, difficulty, score
        self.max_return[index], self.last_sampled[index] = episode_return, self.clock[0]
        self.valid[index] = True
        if content is not None:
            self.content[index] = content
        return index
