"""Level sources: where a resetting environment takes its next level from.

The env asks its source for one level per resetting env, passing each env's episode seed and
difficulty, so a source can be deterministic per (env, episode) whatever the batch does.

``LevelSource`` is the one contract: a source subclasses it, defines ``next_levels`` and
overrides only those of its other facts that differ from the defaults there (a source that keeps
no state of its own, draws no difficulty and learns nothing). The env, the training loop and the
Gymnasium API read those facts from the source, never by probing for them.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from functools import lru_cache
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import torch

from gvgai_pcg.games.rng import mix64
from gvgai_pcg.generators import generate_level, get_generator
from gvgai_pcg.levels import Level, human_levels, resolve_level
from gvgai_pcg.levels.seeds import TRAINING_SEED_SPACE
from gvgai_pcg.levels.sets import load_level_set

if TYPE_CHECKING:
    from tensordict import TensorDictBase

# (env_indices, episode_seeds, difficulties) -> [N] float64, as ``next_levels`` is called
DrawnDifficulties = Callable[[torch.Tensor, torch.Tensor, torch.Tensor], torch.Tensor]


class LevelSource(ABC):
    """Gives the next level of each resetting env. Subclass it and define ``next_levels``; every
    other fact below is declared here with the default of a source that keeps no state, draws no
    difficulty and learns nothing, and a subclass overrides only what is true of it."""

    game: str
    """The game every level of the source is of: the env refuses a source of another game."""

    prepare_ahead: bool = False
    """True where the levels depend on nothing but the env index and the episode seed (nor on any
    state of the source): the env then prepares the next episodes of many envs at once, ahead of
    their resets (``gvgai_pcg.envs.ready_episodes``)."""

    depends_on_difficulty: bool = False
    """True where the levels also depend on the difficulty (generated ones): episodes prepared
    ahead are prepared at each env's difficulty and used only at that difficulty."""

    levels_recur: bool = True
    """False where a level hardly ever comes back (a new generated level each episode): the env
    then compiles each level directly instead of keeping it for reuse."""

    replayed_levels: int = 0
    """For a source that mixes new levels with replays of at most this many (a replay buffer's
    capacity, as PLR⊥'s): the env keeps a level compiled only once it comes back, with room for
    that many, so that new levels, most of which never come back, do not push the replayed ones
    out (``gvgai_pcg.envs.level_bank``). 0: any level may come back, and the env keeps the last
    few it met."""

    level_difficulties: DrawnDifficulties | None = None
    """``level_difficulties(env_indices, episode_seeds, difficulties)``, for a source that draws
    the difficulty of its levels itself (DR): ``[N]`` float64, which the env reports as each env's
    ``level_difficulty``. None: the env reports its own difficulty."""

    observe: Callable[[TensorDictBase], None] | None = None
    """``observe(signals)``, for a source that learns from training: the curriculum's run gives it
    what happened on each level after each batch (``gvgai_pcg.curricula.signals``), or each
    finished episode of a Gymnasium env. None: no signals are computed at all."""

    trains_on: Callable[[TensorDictBase], torch.Tensor | None] | None = None
    """``trains_on(rollout)``, for a source with ``observe`` that keeps steps out of the gradient
    (PLR's robust variant): a ``[B, T]`` bool of the steps the learner learns from, or None for
    all of them. None: the learner learns from every step."""

    between_updates: Callable[[Any, int], bool] | None = None
    """``between_updates(policy, frames)``, for a source that plays the learner's policy itself
    (SFL): the curriculum's run calls it after each update with the acting policy
    (``gvgai_pcg.curricula.base.ActingPolicy``). None: no acting policy is built for it."""

    @abstractmethod
    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        """One level per resetting env: ``env_indices``, ``episode_seeds`` (int64) and
        ``difficulties`` (float64, in [0, 1]) are ``[N]``, on the CPU."""


def single_game(levels: Sequence[Level]) -> str:
    """The one game all ``levels`` are of; an empty or mixed list is refused, and so is a level
    its game's format refuses (a ``Level`` built by hand: ``Level.check``), here rather than in
    a reset or a step."""
    if not levels:
        raise ValueError("a level source needs at least one level")
    games = {level.game for level in levels}
    if len(games) != 1:
        raise ValueError(f"all levels of a source must be of one game, got {sorted(games)}")
    for level in set(levels):
        level.check()
    return games.pop()


class FixedLevel(LevelSource):
    """The same level every episode (the study's Lv X)."""

    prepare_ahead = True  # a function of the env index and episode seed only

    def __init__(self, level: Level) -> None:
        self.game, self.level = single_game([level]), level

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        return [self.level] * len(episode_seeds)

    def __repr__(self) -> str:
        return f"FixedLevel({self.level.name or self.level.game})"


class UniformLevels(LevelSource):
    """A uniform choice among ``levels`` each episode (the study's Lv 0-3), drawn from the
    episode seed so that the choice is reproducible per env."""

    prepare_ahead = True  # a function of the env index and episode seed only

    def __init__(self, levels: Sequence[Level]) -> None:
        self.game, self.levels = single_game(levels), list(levels)

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        picks = (episode_seeds % len(self.levels)).tolist()
        return [self.levels[i] for i in picks]

    def __repr__(self) -> str:
        return f"UniformLevels({[level.name for level in self.levels]})"


class LevelPerEnv(LevelSource):
    """Env i always plays ``levels[i]`` (evaluation: every env of the batch has its own level)."""

    prepare_ahead = True  # a function of the env index and episode seed only

    def __init__(self, levels: Sequence[Level]) -> None:
        self.game, self.levels = single_game(levels), list(levels)

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        return [self.levels[i] for i in env_indices.tolist()]


LEVELS_ACCEPTED = (
    '"human" (the five human levels), a human level\'s name such as zelda_lvl3, a level file, a folder '
    "of level files, a Level, a list of these, or a LevelSource (an instance of a subclass of "
    "gvgai_pcg.envs.LevelSource)"
)


def as_level_source(
    game: str, levels: LevelSource | Level | Sequence[Level | str | PathLike] | str | PathLike
) -> LevelSource:
    """Interpret the ``levels`` argument of ``GVGAIEnv``: a source, a Level, ``"human"`` (the five
    human levels, uniformly), a human level's name (``"zelda_lvl3"``), a level file, a folder of
    level files, or a list of these. One level is played every episode; several, one drawn
    uniformly each episode. Anything else is refused with a ``ValueError`` naming ``levels``."""
    if isinstance(levels, LevelSource):
        source = levels
    elif isinstance(levels, Level):
        source = FixedLevel(levels)
    elif isinstance(levels, str) and levels == "human":
        source = UniformLevels(human_levels(game))
    elif isinstance(levels, str | PathLike | list | tuple):
        items = [levels] if isinstance(levels, str | PathLike) else levels
        if not items:
            raise ValueError(f"levels is an empty list; levels takes {LEVELS_ACCEPTED}")
        resolved = [lv for item in items for lv in _levels_named(game, item)]
        source = FixedLevel(resolved[0]) if len(resolved) == 1 else UniformLevels(resolved)
    else:
        raise ValueError(f"levels={levels!r} is not a choice of levels; levels takes {LEVELS_ACCEPTED}")
    if source.game != game:
        raise ValueError(f"level source is for {source.game!r}, but the env plays {game!r}")
    return source


def _levels_named(game: str, item: Level | str | PathLike) -> list[Level]:
    """The levels one item of ``levels`` stands for: a Level, or the file, folder or human level a
    string names."""
    if isinstance(item, Level):
        return [item]
    if not isinstance(item, str | PathLike):
        raise ValueError(f"levels holds {item!r}, not a level; levels takes {LEVELS_ACCEPTED}")
    if Path(item).exists():
        return load_level_set(game, item)
    try:
        return [resolve_level(str(item), game)]
    except FileNotFoundError:
        raise ValueError(
            f"levels: {str(item)!r} is no level file or folder, nor a level name; "
            f"levels takes {LEVELS_ACCEPTED}"
        ) from None


class GeneratedLevels(LevelSource):
    """A new generated level every episode, at the difficulty given for that env (PCG X, PPCG).

    The level seed comes from the episode seed (in ``[0, TRAINING_SEED_SPACE)``), so every level
    can be regenerated from (generator, difficulty, seed) and is reported as ``level_seed``.
    ``generator`` names any registered generator of the game's levels (a plugin's, say); by
    default the game's own.
    """

    levels_recur = False  # a level comes back once in 2**31 episodes: compiling it is the cheaper way
    prepare_ahead = True  # a function of the env index, the episode seed...
    depends_on_difficulty = True  # ...and the difficulty

    def __init__(self, game: str, generator: str | None = None) -> None:
        self.game, self.generator = game, checked_generator(game, generator)

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        seeds = (episode_seeds % TRAINING_SEED_SPACE).tolist()
        return [
            _generated_of(self.game, self.generator, d, s)
            for d, s in zip(difficulties.tolist(), seeds, strict=True)
        ]

    def __repr__(self) -> str:
        own = "" if self.generator == self.game else f", generator={self.generator!r}"
        return f"GeneratedLevels({self.game!r}{own})"


def checked_generator(game: str, generator: str | None) -> str:
    """The name of the generator a source of ``game`` makes its levels with (default: the game's
    own), checked when the source is built: an unknown one is refused with the registered names."""
    name = generator or game
    get_generator(name)
    return name


def _generated_of(game: str, generator: str, difficulty: float, seed: int) -> Level:
    """A level of ``game`` from ``generator``; a level of another game is refused."""
    level = generate_level(generator, difficulty, seed)
    if level.game != game:
        raise ValueError(f"the generator {generator!r} made a {level.game} level, not a {game} level")
    return level


# Generated levels of a finite set are kept for reuse: a set of up to this many levels is made once.
GENERATED_CACHE = 4096


@lru_cache(maxsize=GENERATED_CACHE)
def generated_level(game: str, generator: str, difficulty: float, seed: int) -> Level:
    """The level (``generator``, ``difficulty``, ``seed``) of ``game``, made once and kept (the
    last ``GENERATED_CACHE``), for sources that draw from a finite set of generated levels again
    and again (a fixed set, a replay buffer)."""
    return _generated_of(game, generator, difficulty, seed)


class GeneratedLevelSet(LevelSource):
    """A fixed, finite set of generated levels: the ``num_levels`` seeds ``start_seed``,
    ``start_seed + 1``, ... at one ``difficulty``, one drawn uniformly each episode from the
    episode seed (PCG X with ``num_levels``; Procgen's ``num_levels`` and ``start_level``).

    Levels are generated when first drawn (and kept, up to ``GENERATED_CACHE``), so a set of a
    million levels costs no more to start than one of ten.
    """

    prepare_ahead = True  # a function of the env index and episode seed only

    def __init__(
        self, game: str, difficulty: float, num_levels: int, start_seed: int = 0, generator: str | None = None
    ) -> None:
        self.generator = checked_generator(game, generator)
        if not 0.0 <= difficulty <= 1.0:
            raise ValueError(f"difficulty must be in [0, 1], got {difficulty}")
        if num_levels < 1:
            raise ValueError(f"a generated level set needs num_levels >= 1, got {num_levels}")
        if start_seed < 0 or start_seed + num_levels > TRAINING_SEED_SPACE:
            raise ValueError(
                f"the seeds {start_seed} .. {start_seed + num_levels - 1} must lie in [0, 2**31) "
                "(the training seeds; the frozen test sets' seeds lie above them)"
            )
        self.game, self.num_levels, self.start_seed = game, int(num_levels), int(start_seed)
        self.difficulty = float(difficulty)

    def level(self, index: int) -> Level:
        """The set's level ``index`` (0 .. num_levels - 1): seed ``start_seed + index``."""
        if not 0 <= index < self.num_levels:
            raise IndexError(f"level {index} of a set of {self.num_levels}")
        return generated_level(self.game, self.generator, self.difficulty, self.start_seed + index)

    def first(self, count: int) -> list[Level]:
        """The set's first ``count`` levels (all of them when it has fewer)."""
        return [self.level(i) for i in range(min(count, self.num_levels))]

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        return [self.level(i) for i in (episode_seeds % self.num_levels).tolist()]

    def __repr__(self) -> str:
        return (
            f"GeneratedLevelSet({self.game!r}, d={self.difficulty:g}, {self.num_levels} levels "
            f"from seed {self.start_seed})"
        )


# DR draws its difficulty from bits of the episode seed that its level seed (the low 31) leaves.
_DR_STREAM = 0x44522D64  # "DR-d"


def uniform_difficulties(episode_seeds: torch.Tensor) -> torch.Tensor:
    """``[N]`` float64 difficulties, uniform on [0, 1), one a function of each episode seed."""
    bits = mix64(episode_seeds.to(torch.int64) ^ _DR_STREAM)
    return ((bits >> 11) & ((1 << 53) - 1)).to(torch.float64) * 2.0**-53


class RandomDifficultyLevels(LevelSource):
    """Domain randomisation: a new generated level every episode at a difficulty drawn uniformly
    from [0, 1] for that env and episode (``uniform_difficulties`` of the episode seed), whatever
    difficulty the env is at. The level is (generator, d, seed) with the seed as in
    ``GeneratedLevels``; the env reports d as ``level_difficulty`` (``level_difficulties``)."""

    levels_recur = False
    prepare_ahead = True  # a function of the env index and episode seed only

    def __init__(self, game: str, generator: str | None = None) -> None:
        self.game, self.generator = game, checked_generator(game, generator)

    def level_difficulties(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> torch.Tensor:
        return uniform_difficulties(episode_seeds)

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        drawn = uniform_difficulties(episode_seeds).tolist()
        seeds = (episode_seeds % TRAINING_SEED_SPACE).tolist()
        return [_generated_of(self.game, self.generator, d, s) for d, s in zip(drawn, seeds, strict=True)]

    def __repr__(self) -> str:
        own = "" if self.generator == self.game else f", generator={self.generator!r}"
        return f"RandomDifficultyLevels({self.game!r}{own})"
