"""SFL, sampling for learnability (Rutherford et al. 2024, "No Regrets: Investigating and Improving
Regret Approximations for Curriculum Discovery"; github.com/amacrutherford/sampling-for-learnability).

Every refresh, SFL samples a pool of generated levels (d ~ U[0, 1], a new seed each), plays the
current policy on each of them a few times, scores each level's learnability p(1 - p) with p its
win rate (highest at p = 1/2: levels the agent sometimes solves), and keeps the top
``buffer_size`` in a buffer. Between refreshes every episode plays a buffer level with
probability ``replay_probability`` and a fresh DR level otherwise (``RandomDifficultyLevels``).

Defaults (``conf/regimen/sfl.yaml``). The reference's MiniGrid config samples 5 x 5,000 levels,
rolls each out for 2,000 steps, keeps the top 1,000 and refreshes every 100 updates of 256 envs x
256 steps (6.6M frames); half the envs train on buffer levels (``replay_probability`` 0.5). On a
2-core CPU that pool would cost more than the training it steers, so ours are CPU-sized: a pool of
``pool_size`` 200 levels, ``pool_episodes`` 4 episodes each (p is a fraction of 4), at most
``rollout_steps`` 1,000 steps an episode, the top ``buffer_size`` 50 kept, a refresh every
``refresh_every_frames`` 1M frames (and at the first update, so the buffer is never empty for
long). One refresh of these defaults with the pilot's trained Zelda model (10M frames) costs about
22 s of CPU on one thread, about 30 % on top of the ~70 s that 1M frames of A2C take on a quiet
2-core machine (docs/concepts/regimens.md, ``sfl``; docs/benchmarks.md). A level is (generator,
d, seed), so the buffer keeps three numbers a level.

The refresh needs the policy: after each update the training loop calls its curriculum run's
``between_updates(policy, frames)``, which calls the level source's (``gvgai_pcg.rl.training``).
The buffer lives in the curriculum's ``SharedState`` (shared with collector workers, kept in
checkpoints), so a resumed run keeps its buffer, and the pools are drawn from the run's seed
and the refresh count.
"""

from __future__ import annotations

import math

import torch

from gvgai_pcg.config_rules import WIN_RULES, ConfigError, Integer, Number, OneOf, Text
from gvgai_pcg.curricula.base import ActingPolicy, Curriculum
from gvgai_pcg.curricula.state import SharedState
from gvgai_pcg.envs import GVGAIEnv, LevelPerEnv
from gvgai_pcg.envs.level_sources import LevelSource, RandomDifficultyLevels
from gvgai_pcg.games.rng import derive_seeds, mix64
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels.seeds import TRAINING_SEED_SPACE

_REPLAY_STREAM = 0x53464C72  # "SFLr": whether an episode replays a buffer level
_PICK_STREAM = 0x53464C70  # "SFLp": which buffer level


class LearnabilityBuffer(SharedState):
    """The top levels of the last refresh, as (d, seed, learnability), and when it was made."""

    def __init__(self, size: int) -> None:
        super().__init__()
        self.register_shared("difficulties", torch.zeros(size, dtype=torch.float64))
        self.register_shared("seeds", torch.zeros(size, dtype=torch.int64))
        self.register_shared("learnability", torch.zeros(size, dtype=torch.float64))
        self.register_shared("filled", torch.zeros(1, dtype=torch.int64))  # levels held (0: none yet)
        self.register_shared("refreshes", torch.zeros(1, dtype=torch.int64))
        self.register_shared("refreshed_at", torch.zeros(1, dtype=torch.int64))  # frames

    @property
    def size(self) -> int:
        return int(self.filled[0])

    @property
    def difficulty(self) -> float:
        """The mean d of the buffer's levels (the log's difficulty column; NaN while empty)."""
        return float(self.difficulties[: self.size].mean()) if self.size else math.nan

    def replace(
        self, difficulties: torch.Tensor, seeds: torch.Tensor, scores: torch.Tensor, frames: int
    ) -> None:
        count = len(seeds)
        with self.lock:
            self.difficulties[:count] = difficulties
            self.seeds[:count] = seeds
            self.learnability[:count] = scores
            self.filled[0] = count
            self.refreshes[0] += 1
            self.refreshed_at[0] = frames


def learnability(wins: torch.Tensor) -> torch.Tensor:
    """``[L]`` p(1 - p) of ``wins`` ``[L, E]`` (E episodes of each of L levels), p the win rate."""
    p = wins.to(torch.float64).mean(-1)
    return p * (1 - p)


def top_levels(scores: torch.Tensor, count: int) -> torch.Tensor:
    """Indices of the ``count`` highest ``scores``, highest first (ties: the earlier level)."""
    order = torch.argsort(-scores, stable=True)
    return order[:count]


def play_wins(
    game: str, levels: list, policy: ActingPolicy, episodes: int, max_steps: int, seed: int
) -> torch.Tensor:
    """``[L, episodes]`` whether each of ``episodes`` episodes of each level was won (one batched
    env, one episode per env; an episode still running at ``max_steps`` counts as lost)."""
    batch = [level for level in levels for _ in range(episodes)]
    env = GVGAIEnv(
        game,
        num_envs=len(batch),
        levels=LevelPerEnv(batch),
        obs=policy.obs,
        max_steps=max_steps,
        device=policy.device,
        seed=derive_seeds(seed, len(batch)).tolist(),
        compile_tick=False,  # a pool's few thousand steps do not pay a compilation back
    )
    try:
        wins = torch.zeros(len(batch), dtype=torch.bool)
        finished = torch.zeros(len(batch), dtype=torch.bool)
        td = env.reset()
        for _ in range(max_steps):
            with torch.no_grad():
                td.set("action", policy.act(td))
            td = env.step(td).get("next")
            done = td.get("done").squeeze(-1).cpu() & ~finished
            wins |= done & td.get("won").squeeze(-1).cpu()
            finished |= done
            if bool(finished.all()):
                break
    finally:
        env.close()
    return wins.reshape(len(levels), episodes)


class LearnabilityLevels(LevelSource):
    """SFL's level source: a buffer level with probability ``replay_probability``, else a DR level,
    each chosen from the episode seed (so reproducible per env and episode, given the buffer)."""

    levels_recur = False  # mostly fresh generated levels; a buffer of 50 is regenerated cheaply
    prepare_ahead = False  # its levels depend on the buffer

    def __init__(self, game: str, section, state: LearnabilityBuffer) -> None:
        self.game, self.state = game, state
        self.fresh = RandomDifficultyLevels(game)
        self.replay_probability = float(section["replay_probability"])
        self.pool_size = int(section["pool_size"])
        self.pool_episodes = int(section["pool_episodes"])
        self.rollout_steps = int(section["rollout_steps"])
        self.refresh_every_frames = int(section["refresh_every_frames"])

    def _replayed(self, episode_seeds: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Which episodes replay a buffer level, and which one (bits of the episode seed that
        neither the level seed nor DR's d use)."""
        size = self.state.size
        if size == 0:
            return torch.zeros(len(episode_seeds), dtype=torch.bool), torch.zeros_like(episode_seeds)
        seeds = episode_seeds.to(torch.int64)
        replay_bits = (mix64(seeds ^ _REPLAY_STREAM) >> 11) & ((1 << 53) - 1)
        replay = replay_bits.to(torch.float64) * 2.0**-53 < self.replay_probability
        pick = ((mix64(seeds ^ _PICK_STREAM) >> 1) & ((1 << 62) - 1)) % size
        return replay, pick

    def level_difficulties(self, env_indices, episode_seeds, difficulties) -> torch.Tensor:
        replay, pick = self._replayed(episode_seeds)
        fresh = self.fresh.level_difficulties(env_indices, episode_seeds, difficulties)
        return torch.where(replay, self.state.difficulties[pick], fresh)

    def next_levels(self, env_indices, episode_seeds, difficulties) -> list:
        replay, pick = self._replayed(episode_seeds)
        fresh = self.fresh.next_levels(env_indices, episode_seeds, difficulties)
        d, seeds = self.state.difficulties[pick].tolist(), self.state.seeds[pick].tolist()
        return [
            generate_level(self.game, d[i], seeds[i]) if replay[i] else fresh[i] for i in range(len(fresh))
        ]

    def between_updates(self, policy: ActingPolicy, frames: int) -> bool:
        """Refresh the buffer when it is empty or ``refresh_every_frames`` have passed; whether it did."""
        due = int(self.state.refreshed_at[0]) + self.refresh_every_frames
        if self.state.size and frames < due:
            return False
        self.refresh(policy, frames)
        return True

    def refresh(self, policy: ActingPolicy, frames: int) -> None:
        """Sample a pool, play it, keep its most learnable levels."""
        # the run's seed (seed_everything) and the refresh count: a resumed run draws the next pool
        pool_seed = (torch.initial_seed() * 1_000_003 + int(self.state.refreshes[0])) % 2**63
        generator = torch.Generator().manual_seed(pool_seed)
        difficulties = torch.rand(self.pool_size, generator=generator, dtype=torch.float64)
        seeds = torch.randint(0, TRAINING_SEED_SPACE, (self.pool_size,), generator=generator)
        levels = [
            generate_level(self.game, d, s)
            for d, s in zip(difficulties.tolist(), seeds.tolist(), strict=True)
        ]
        play_seed = int(torch.randint(0, 2**62, (1,), generator=generator))
        wins = play_wins(self.game, levels, policy, self.pool_episodes, self.rollout_steps, play_seed)
        scores = learnability(wins)
        top = top_levels(scores, len(self.state.seeds))
        self.state.replace(difficulties[top], seeds[top], scores[top], frames)

    def __repr__(self) -> str:
        return f"LearnabilityLevels({self.game!r}, {self.state.size} buffered)"


class SamplingForLearnability(Curriculum):
    """SFL: the top of a pool of generated levels by learnability p(1 - p), refreshed with the
    current policy, mixed with fresh DR levels."""

    name, summary, label = (
        "sfl",
        "SFL: the most learnable of a pool of generated levels, mixed with DR",
        "SFL",
    )
    generated = True
    learner_needs = "the learner's policy (it plays it on a pool of levels between updates)"
    schema = {
        "name": Text(),
        "replay_probability": Number(0.0, 1.0),
        "buffer_size": Integer(1, 100_000),
        "pool_size": Integer(1, 1_000_000),
        "pool_episodes": Integer(2, 1000),
        "rollout_steps": Integer(1, 100_000),
        "refresh_every_frames": Integer(1),
        "win_rule": OneOf(WIN_RULES),
        "tag": Text(),
    }

    def check(self, section, config) -> None:
        if int(section["buffer_size"]) > int(section["pool_size"]):
            raise ConfigError(
                f"regimen.buffer_size={section['buffer_size']} is more than regimen.pool_size="
                f"{section['pool_size']}: the buffer keeps the top of one pool"
            )

    def make_state(self, game, section):
        buffer = LearnabilityBuffer(int(section["buffer_size"]))
        buffer.game = game  # whose levels replay_levels rebuilds
        return buffer

    def replay_levels(self, state, k):
        """The buffer's ``k`` most learnable levels, most learnable first."""
        held = 0 if state is None else int(state.filled[0])
        order = torch.argsort(state.learnability[:held], descending=True, stable=True)[:k] if held else []
        return [generate_level(state.game, float(state.difficulties[i]), int(state.seeds[i])) for i in order]

    def make_source(self, game, section, state=None):
        return LearnabilityLevels(game, section, state or self.make_state(game, section))


CURRICULUM = SamplingForLearnability()
