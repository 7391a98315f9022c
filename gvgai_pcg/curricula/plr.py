"""PLR⊥, robust Prioritized Level Replay (Jiang, Dennis, Parker-Holder, Foerster, Grefenstette and
Rocktäschel 2021, "Replay-Guided Adversarial Environment Design"), as a curriculum:
``regimen=plr`` (``conf/regimen/plr.yaml``; its parameters and their sources: docs/curricula.md).

Each resetting env either replays a level of the shared ``LevelBuffer`` (with probability
``replay_prob``, once the buffer is ``rho`` full), drawn by rank-prioritised score mixed with
staleness, or plays a new generated level at d ~ U[``min_difficulty``, ``max_difficulty``]
(DR's draw, from the episode seed). After each batch ``observe`` scores every finished episode
(``score: pvl``, positive value loss: the mean of max(advantage, 0) over the episode's steps;
``score: maxmc``: the level's highest return minus the mean value estimate), updates the score of
a replayed level and offers a new one to the buffer. Episodes that run across batches carry
their partial sums until they end: an unfinished episode never writes a score.

Robust (``robust: true``): the learner takes gradients only from the steps of replayed levels.
The decision here is per env and episode (dcd and JaxUED decide per rollout of all envs), so
``trains_on`` marks, per step, the levels that were in the buffer before the batch: the training
loop passes it to the learner as the rollout's ``train_mask``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import torch
from tensordict import TensorDictBase

from gvgai_pcg.config_rules import DIFFICULTY, WIN_RULES, ConfigError, Flag, Integer, Number, OneOf, Text
from gvgai_pcg.curricula.base import Curriculum
from gvgai_pcg.curricula.level_buffer import LevelBuffer
from gvgai_pcg.envs.level_sources import LevelSource, checked_generator, generated_level, uniform_difficulties
from gvgai_pcg.games.rng import mix64
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.seeds import TRAINING_SEED_SPACE

SCORES = ("pvl", "maxmc")
_REPLAY_STREAM, _PICK_STREAM = 0x504C522D72, 0x504C522D70  # "PLR-r", "PLR-p": bits of the episode seed


def seed_uniforms(episode_seeds: torch.Tensor, stream: int) -> torch.Tensor:
    """``[N]`` float64 uniforms on [0, 1), one a function of each episode seed and ``stream``."""
    bits = mix64(episode_seeds.to(torch.int64) ^ stream)
    return ((bits >> 11) & ((1 << 53) - 1)).to(torch.float64) * 2.0**-53


@dataclass(frozen=True)
class ReplaySettings:
    """The knobs of PLR⊥ (``conf/regimen/plr.yaml``)."""

    buffer_size: int = 4000
    score: str = "pvl"
    temperature: float = 0.3
    staleness_coef: float = 0.3
    replay_prob: float = 0.5
    rho: float = 0.5
    min_difficulty: float = 0.0
    max_difficulty: float = 1.0
    robust: bool = True

    @classmethod
    def of(cls, section: Mapping[str, Any]) -> ReplaySettings:
        known = {key: section[key] for key in cls.__dataclass_fields__ if key in section}
        return cls(**known)


@dataclass
class Episode:
    """An episode's running sums, across batches, until it ends."""

    seed: int
    difficulty: float
    steps: int = 0
    positive_advantage: float = 0.0  # sum over steps of max(advantage, 0)
    value: float = 0.0  # sum over steps of V(s)

    def score(self, kind: str, best_return: float) -> float:
        if self.steps <= 0:
            return math.nan
        if kind == "maxmc":
            return best_return - self.value / self.steps
        return self.positive_advantage / self.steps


class PrioritizedLevels(LevelSource):
    """PLR⊥'s level source: a replayed level of the buffer or a new generated one per resetting
    env (``next_levels``), and the scores of finished episodes into the buffer (``observe``).

    The buffer is shared by every env and worker; the partial episodes of ``observe`` belong to
    the one source the training loop feeds (in its own process)."""

    prepare_ahead = False  # its levels depend on the buffer

    def __init__(
        self, game: str, buffer: LevelBuffer, settings: ReplaySettings, generator: str | None = None
    ) -> None:
        self.game, self.buffer, self.settings = game, buffer, settings
        self.replayed_levels = buffer.capacity  # every level of the buffer may be replayed
        self.generator = checked_generator(game, generator)
        self._handed_d: dict[int, float] = {}  # env index -> the d of the level it was last handed
        self._running: dict[int, Episode] = {}  # env row -> its episode still running at the batch's end

    # --- handing out levels (every env, in its own process) ---
    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        s = self.settings
        replay_draws = seed_uniforms(episode_seeds, _REPLAY_STREAM).tolist()
        pick_draws = seed_uniforms(episode_seeds, _PICK_STREAM).tolist()
        levels = []
        with self.buffer.lock:
            for k, env in enumerate(env_indices.tolist()):
                self.buffer.tick()
                level, d = self._special_level(env, episode_seeds[k])
                if level is None:
                    if self._replays_now() and replay_draws[k] < s.replay_prob:
                        probabilities = self.buffer.replay_probabilities(s.temperature, s.staleness_coef)
                        index = self.buffer.pick(probabilities, pick_draws[k])
                        level, d = self.replayed_level(index), float(self.buffer.level_d[index])
                    else:
                        level, d = self.new_level(int(episode_seeds[k]))
                self._handed_d[env] = d
                levels.append(level)
        return levels

    def new_level(self, episode_seed: int) -> tuple[Level, float]:
        """The new generated level of an episode that replays none, and its d: DR's draw of the
        episode seed, scaled to [``min_difficulty``, ``max_difficulty``], and the seed's low bits.
        Drawn only for the envs that play one (a replay draws nothing here)."""
        s = self.settings
        drawn = float(uniform_difficulties(torch.tensor([episode_seed]))[0])
        d = s.min_difficulty + (s.max_difficulty - s.min_difficulty) * drawn
        return self.generated_level(d, episode_seed % TRAINING_SEED_SPACE), d

    def _special_level(self, env: int, episode_seed: torch.Tensor) -> tuple[Level | None, float]:
        """A level that comes before the replay decision (ACCEL's edited ones), or ``None``."""
        return None, 0.0

    def _replays_now(self) -> bool:
        """Replays start once the buffer is ``rho`` full (dcd's ``level_replay_rho``), never empty."""
        return self.buffer.size > 0 and self.buffer.filled >= self.settings.rho

    def level_difficulties(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> torch.Tensor:
        """The d of the levels just handed to ``env_indices`` (the env reports it)."""
        return torch.tensor([self._handed_d[i] for i in env_indices.tolist()], dtype=torch.float64)

    def generated_level(self, difficulty: float, seed: int) -> Level:
        return generated_level(self.game, self.generator, difficulty, seed)

    def replayed_level(self, index: int) -> Level:
        """The buffer's level ``index`` (regenerated from its d and seed; kept in a cache)."""
        return self.generated_level(float(self.buffer.level_d[index]), int(self.buffer.seed[index]))

    # --- learning from training (the training loop's process) ---
    def trains_on(self, rollout: TensorDictBase) -> torch.Tensor | None:
        """``[B, T]`` bool: the steps the learner may take gradients from (robust: those of levels
        in the buffer before this batch, i.e. replayed; else ``None``, every step)."""
        if not self.settings.robust:
            return None
        nxt = rollout.get("next")
        shape = rollout.batch_size
        seeds = nxt.get("level_seed").reshape(shape).cpu()
        difficulties = nxt.get("level_difficulty").reshape(shape).cpu().to(torch.float64)
        pairs = torch.stack([seeds.flatten(), difficulties.flatten().view(torch.int64)])
        unique, inverse = torch.unique(pairs, dim=1, return_inverse=True)
        with self.buffer.lock:
            found = self.buffer.find(unique[0], unique[1].view(torch.float64)) >= 0
        return found[inverse].reshape(shape).to(rollout.device)

    def observe(self, signals: TensorDictBase) -> None:
        """Score the episodes that ended in this batch; carry the others to the next."""
        kind = self.settings.score
        needed = "state_value" if kind == "maxmc" else "advantage_positive"
        if needed not in signals.keys():
            raise ValueError(
                f"regimen plr (score={kind}) needs the learner's per-step {needed!r}; this learner gives none"
            )
        finished: list[tuple[Episode, float]] = []
        columns = {
            key: signals[key].tolist()
            for key in ("env", "level_seed", "level_difficulty", "steps", "finished", "return")
        }
        learned = {
            key: signals[key].tolist() for key in ("advantage_positive", "state_value") if key in signals
        }
        for k, env in enumerate(columns["env"]):
            seed, d, steps = columns["level_seed"][k], columns["level_difficulty"][k], columns["steps"][k]
            episode = self._running.pop(env, None)
            if episode is None or (episode.seed, episode.difficulty) != (seed, d):
                episode = Episode(seed, d)  # a new episode (or one whose start was before this source)
            episode.steps += steps
            if "advantage_positive" in learned:
                episode.positive_advantage += learned["advantage_positive"][k] * steps
            if "state_value" in learned:
                episode.value += learned["state_value"][k] * steps
            if columns["finished"][k]:
                finished.append((episode, float(columns["return"][k])))
            else:
                self._running[env] = episode
        if finished:
            with self.buffer.lock:
                self._score(finished)

    def _score(self, finished: list[tuple[Episode, float]]) -> None:
        """Write the scores of ``finished`` episodes into the buffer (inside its lock)."""
        seeds = torch.tensor([episode.seed for episode, _ in finished], dtype=torch.int64)
        difficulties = torch.tensor([episode.difficulty for episode, _ in finished], dtype=torch.float64)
        indices = self.buffer.find(seeds, difficulties).tolist()
        for (episode, episode_return), index in zip(finished, indices, strict=True):
            best = episode_return if index < 0 else max(float(self.buffer.max_return[index]), episode_return)
            score = episode.score(self.settings.score, best)
            if not math.isfinite(score):
                continue  # never poison the buffer
            if index >= 0:
                self.buffer.update(index, score, episode_return)
                self._replayed(index, episode)
            else:
                self._offer(episode, score, episode_return)

    def _replayed(self, index: int, episode: Episode) -> None:
        """A replayed level's episode was scored (ACCEL edits it)."""

    def _offer(self, episode: Episode, score: float, episode_return: float) -> int:
        """Offer a new level to the buffer; its index, or -1."""
        if episode.seed < 0 or episode.seed >= TRAINING_SEED_SPACE:
            return -1  # not a level of the generator
        return self.buffer.insert(episode.seed, episode.difficulty, score, episode_return)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.game!r}, {self.buffer.size}/{self.buffer.capacity} levels)"


class PrioritizedLevelReplay(Curriculum):
    """PLR⊥: a bounded buffer of generated levels replayed by score and staleness, new levels at
    d ~ U[min_difficulty, max_difficulty], gradients only from replays (``robust``)."""

    name, summary, label = "plr", "PLR⊥: robust prioritized level replay of generated levels", "PLR⊥"
    generated = True
    learner_needs = "the learner's value estimates (it scores levels by positive value loss or MaxMC)"
    schema = {
        "name": Text(),
        "buffer_size": Integer(1, 1_000_000),
        "score": OneOf(SCORES),
        "temperature": Number(0.0, low_open=True),
        "staleness_coef": Number(0.0, 1.0),
        "replay_prob": Number(0.0, 1.0),
        "rho": Number(0.0, 1.0),
        "min_difficulty": DIFFICULTY,
        "max_difficulty": DIFFICULTY,
        "robust": Flag(),
        "win_rule": OneOf(WIN_RULES),
        "tag": Text(),
    }
    source_type: type[PrioritizedLevels] = PrioritizedLevels

    def check(self, section, config):
        low, high = section["min_difficulty"], section["max_difficulty"]
        if low > high:
            raise ConfigError(f"regimen.min_difficulty={low}: expected at most regimen.max_difficulty={high}")
        if section["robust"] and section["replay_prob"] == 0:
            raise ConfigError(
                "regimen.replay_prob=0: expected more than 0 with regimen.robust=true, which takes "
                "gradients from replayed levels only: no level is ever replayed, so the learner would "
                "never take a step; set regimen.replay_prob > 0, or regimen.robust=false"
            )

    def make_state(self, game, section):
        buffer = LevelBuffer(int(section.get("buffer_size", ReplaySettings.buffer_size)))
        buffer.game = game  # whose levels replay_levels rebuilds
        return buffer

    def replay_levels(self, state, k):
        """The buffer's ``k`` highest-scoring levels, highest first: rank prioritisation replays
        them most (staleness aside)."""
        if state is None or not bool(state.valid.any()):
            return []
        source = self.make_source(state.game, {}, state)
        scores = torch.where(state.valid, state.score.to(torch.float64), -math.inf)
        best = torch.argsort(scores, descending=True, stable=True)[: min(k, int(state.valid.sum()))]
        return [source.replayed_level(int(index)) for index in best]

    def make_source(self, game, section, state=None):
        buffer = state if state is not None else self.make_state(game, section)
        return self.source_type(game, buffer, ReplaySettings.of(section))


CURRICULUM = PrioritizedLevelReplay()
