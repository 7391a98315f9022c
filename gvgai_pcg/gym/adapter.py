"""``GVGAIGymEnv``: one game as a Gymnasium ``Env``, for CleanRL, Stable-Baselines3 and plain loops.

It is a thin view of a ``GVGAIEnv`` with a batch of one, so the rules, observations, seeds and
step limit are exactly the TorchRL env's: ``reset(seed=s)`` followed by the same actions gives
the same trajectory as ``GVGAIEnv(game, 1, seed=s)``. The training regimens of the study
(Lv X, Lv 0-3, PCG X, Progressive PCG) are chosen by name; the difficulty of generated levels
is owned by the curriculum's run (``CurriculumRun``, as in the trainer), so the curriculum rule
lives in one place.
Once an episode has ended (``terminated`` or ``truncated``), ``step`` refuses until ``reset``:
the engine would otherwise go on playing (after a truncation) or stay frozen (after a
termination) without saying so.

A curriculum whose level source learns (``observe``) gets, through its run, after every step,
one row per episode that ended at it: the level (seed and d), return, win and length
(``EpisodeOutcomes``). That is all a Gymnasium env knows: it has no learner, so a curriculum that
needs one (PLR⊥ and ACCEL score levels by the learner's value estimates, SFL plays its policy)
is refused by name; ``gvgai-pcg train`` runs those.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import torch
from tensordict import TensorDict, TensorDictBase

import gvgai_pcg.envs.quiet_torchrl  # noqa: F401 (first: torchrl without its global side effect)
from gvgai_pcg.curricula.signals import EpisodeOutcomes
from gvgai_pcg.envs.gvgai_env import GVGAIEnv
from gvgai_pcg.envs.inputs import checked_observation_kind
from gvgai_pcg.envs.level_sources import LevelSource
from gvgai_pcg.games import get_game
from gvgai_pcg.games.geometry import CELL
from gvgai_pcg.gym.regimens import (
    given_source,
    regimen_kind,
    regimen_run,
    regimens_taking,
    unused_arguments,
)
from gvgai_pcg.levels import Level, human_level, human_levels, resolve_level
from gvgai_pcg.levels.sets import load_level_set

RENDER_MODES = ("rgb_array", "ansi", "human")

LevelSpec = Level | str | int
LevelSetSpec = str | Path | Sequence[Level | str | Path]


def _resolve(game: str, spec: LevelSpec) -> Level:
    """A level from a Level, a human level index, a name (``zelda_lvl3``), a file path, or the
    level's text itself (several lines)."""
    if isinstance(spec, Level):
        if spec.game != game:
            raise ValueError(f"level {spec.name or '<unnamed>'} is a {spec.game} level, not a {game} level")
        return spec
    if isinstance(spec, int | np.integer) and not isinstance(spec, bool):
        return human_level(game, int(spec))
    if not isinstance(spec, str | Path):
        raise ValueError(
            f"level: expected a Level, a human level index, a {game} level name, a level file or a "
            f"level's text; got {type(spec).__name__} {_shown(spec)}"
        )
    text = str(spec)
    if "\n" in text.strip():
        return Level.parse(text, game)
    try:
        return resolve_level(text, game)
    except OSError:  # no such file, or a name too long to be one
        raise ValueError(
            f"level {_shown(text)} is neither a {game} level name ({game}_lvl0 .. {game}_lvl4), a level "
            "file, nor a level's text"
        ) from None


def _shown(value: Any, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters: an error stays one readable line."""
    text = repr(value)
    return text if len(text) <= limit else f"{text[: limit - 3]}..."


def _level_set(game: str, spec: LevelSetSpec) -> list[Level]:
    """The levels of a set: a folder or file path, or a list of paths and Levels."""
    if isinstance(spec, str | Path):
        return load_level_set(game, spec)
    return [
        lv
        for item in spec
        for lv in ([_resolve(game, item)] if isinstance(item, Level) else load_level_set(game, item))
    ]


class LevelOverrides(LevelSource):
    """A level source that plays a requested level once, then defers to the regimen's source.

    ``reset(options={"level": ...})`` needs this: the env asks its source for the next level of
    every resetting env, and a pending request wins over the regimen for that one episode.
    """

    def __init__(self, source: LevelSource, num_envs: int) -> None:
        self.source, self.game = source, source.game
        self._pending: list[Level | None] = [None] * num_envs
        # DR draws each level's difficulty: the env reports it as its own
        self.level_difficulties = source.level_difficulties

    def request(self, env_indices: Sequence[int], level: Level) -> None:
        for i in env_indices:
            self._pending[i] = level

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        levels = self.source.next_levels(env_indices, episode_seeds, difficulties)
        for k, i in enumerate(env_indices.tolist()):
            if self._pending[i] is not None:
                levels[k], self._pending[i] = self._pending[i], None
        return levels


class Regimen:
    """Where levels come from and, for generated levels, the difficulty they are made at.

    Args:
        game: the game name.
        regimen: ``"lv"`` (every episode on ``level``: a human level index, a name, a path or a
            Level, or a list of them played uniformly), ``"lv0-3"`` (human levels 0-3
            uniformly), ``"human"`` (all five human levels), ``"levels"`` (your own set
            ``levels``, uniformly), ``"pcg"`` (generated levels at the fixed ``difficulty``: a
            new one every episode, or a set of ``num_levels`` from seed ``start_seed``) or
            ``"ppcg"`` (generated levels; the difficulty starts at ``difficulty`` and moves by
            ``alpha`` per finished episode).
        win_rule: what raises the PPCG difficulty (see ``DifficultyTransform``).
        levels: the ``levels`` regimen's set: a folder of level files, a file, or a list of
            files, folders and Levels.
        num_levels: ``pcg`` only: 0 for a new level every episode, N for a fixed set of N.
        start_seed: ``pcg`` with ``num_levels``: the seed of the set's first level.
    """

    def __init__(
        self,
        game: str,
        regimen: str,
        num_envs: int,
        level: LevelSpec | Sequence[LevelSpec] = 0,
        difficulty: float | None = None,
        alpha: float | None = None,
        win_rule: str = "game",
        levels: LevelSetSpec | None = None,
        num_levels: int = 0,
        start_seed: int = 0,
    ) -> None:
        kind = regimen_kind(regimen)
        if kind.learner_needs:
            raise ValueError(
                f"regimen {regimen!r} needs {kind.learner_needs}, which a Gymnasium env does not have; "
                f"train with it through gvgai-pcg train regimen={regimen}"
            )
        if (levels is not None) != (regimen == "levels"):
            raise ValueError("levels= gives the set of regimen='levels', and that regimen needs it")
        difficulty, alpha = _used_arguments(regimen, difficulty, alpha)
        self.game, self.name, self.finite, self.num_envs = game, regimen, num_levels > 0, num_envs
        # each env's own difficulty from a per-env reset option (NaN: the regimen's)
        self._env_difficulty = torch.full((num_envs,), math.nan, dtype=torch.float64)
        # the run owns the level choice, as the trainer's does: its state, source and signals
        self.run = regimen_run(game, regimen, difficulty, alpha, win_rule, num_levels, start_seed)
        # the difficulty that PCG X and PPCG hand out; another curriculum's state is its own
        self.curriculum = self.run.settable_difficulty
        given: list[Level] | None = None
        if regimen == "levels":
            given = _level_set(game, levels)
        elif regimen == "lv":
            specs = level if isinstance(level, list | tuple) else [level]
            given = [_resolve(game, spec) for spec in specs]
        elif regimen == "lv0-3":
            given = [human_level(game, i) for i in range(4)]
        elif not kind.generated:
            given = human_levels(game)
        source = given_source(game, regimen, given or []) if not kind.generated else self.run.learner_source
        self.source = LevelOverrides(source, num_envs)
        # given levels come from the caller, not the section: only a generated regimen's run learns
        self.outcomes = EpisodeOutcomes(num_envs) if kind.generated and self.run.learns else None

    @property
    def difficulty(self) -> float:
        """The difficulty the next generated level is made at (0 for human-level regimens)."""
        return self.curriculum.difficulty if self.curriculum is not None else 0.0

    def set_difficulty(self, value: float) -> None:
        """Every env's generated levels at ``value`` from now on (per-env ones forgotten)."""
        self.curriculum.shared_difficulty[0] = self._checked_difficulty(value)
        self._env_difficulty.fill_(math.nan)

    def env_difficulties(self) -> torch.Tensor:
        """The difficulty each env's next generated level is made at: ``[B]`` float64."""
        own = self._env_difficulty
        return torch.where(own.isnan(), torch.full_like(own, self.difficulty), own)

    def _checked_difficulty(self, value: float) -> float:
        if self.curriculum is None and regimen_kind(self.name).generated:
            raise ValueError(
                f"regimen {self.name!r} chooses the difficulty of its levels itself; "
                "use regimen='pcg' or 'ppcg' to set it"
            )
        if self.curriculum is None:
            raise ValueError(
                f"regimen {self.name!r} plays {'your own' if self.name == 'levels' else 'human'} levels, "
                "so a difficulty has no effect; "
                f"use regimen='pcg' or 'ppcg' for generated levels"
            )
        if self.finite:
            raise ValueError(
                "a fixed set of generated levels (num_levels >= 1) keeps the difficulty it was made at"
            )
        if not 0.0 <= value <= 1.0:
            raise ValueError(f"difficulty must be in [0, 1], got {value}")
        return float(value)

    def record(
        self, next_td: TensorDictBase, finished: torch.Tensor, stepped: torch.Tensor | None = None
    ) -> None:
        """After every step, the run's two signals: the episodes that ended (``finished``: ``[B]``
        bool; PPCG moves its d once per episode, in env order, as its transform does in the
        trainer's step), and, to a curriculum that learns, their rows (``stepped``: the envs
        that played this step, all by default)."""
        self.run.episodes_ended(next_td, finished)
        if self.outcomes is not None:
            rows = self.outcomes(next_td, torch.ones_like(finished) if stepped is None else stepped)
            if rows is not None:
                self.run.observe(rows)

    def restart(self, mask: torch.Tensor) -> None:
        """The envs in ``mask`` (``[B]`` bool) start new episodes (a reset)."""
        if self.outcomes is not None:
            self.outcomes.restart(mask)

    def reset_tensordict(self, mask: torch.Tensor, device: torch.device) -> TensorDict:
        """The tensordict that asks the env to reset the envs in ``mask`` (``[B]`` bool)."""
        b = mask.shape[0]
        return TensorDict(
            {
                "_reset": mask.reshape(b, 1).to(device),
                "difficulty": self.env_difficulties().reshape(b, 1).to(device),
            },
            batch_size=[b],
            device=device,
        )

    def check_options(self, options: dict[str, Any] | None, vector: bool = False) -> ResetOptions:
        """Reset options, checked before anything changes: ``level`` (played by the resetting envs
        this episode), ``difficulty``, and for a vector env ``reset_mask`` (which it reads itself).
        ``level`` and ``difficulty`` each take one value for every env or a list of one per env."""
        options = options or {}
        valid = ("level", "difficulty", "reset_mask") if vector else ("level", "difficulty")
        unknown = set(options) - set(valid)
        if unknown:
            choices = ", ".join(valid)
            raise ValueError(f"unknown reset options {sorted(unknown)}; valid options are: {choices}")
        difficulty, level = options.get("difficulty"), options.get("level")
        if difficulty is None:
            checked: float | tuple[float, ...] | None = None
        elif _per_env(difficulty):
            checked = tuple(
                self._checked_env_difficulty(d) for d in self._one_per_env("difficulty", difficulty)
            )
        else:
            checked = self._checked_difficulty(_number("difficulty", difficulty, self.num_envs))
        levels = None
        if level is not None:
            specs = self._one_per_env("level", level) if _per_env(level) else [level] * self.num_envs
            levels = tuple(None if spec is None else _resolve(self.game, spec) for spec in specs)
        return ResetOptions(checked, levels)

    def _one_per_env(self, name: str, values: Any) -> list[Any]:
        """``values`` (a list, tuple or 1-D array) as a list of ``num_envs`` items, or one line."""
        items = (
            list(np.asarray(values, dtype=object).reshape(-1))
            if isinstance(values, np.ndarray)
            else list(values)
        )
        if len(items) != self.num_envs or (isinstance(values, np.ndarray) and values.ndim != 1):
            raise ValueError(
                f"reset option {name}: one value for every env, or a list of {self.num_envs} (one per env); "
                f"got {len(items)} values"
            )
        return items

    def _checked_env_difficulty(self, value: Any) -> float:
        """One env's entry of a per-env ``difficulty``: where the regimen has a difficulty of each
        env's own (``pcg``, a new level every episode), a number in [0, 1]."""
        number = _number("difficulty", value, self.num_envs)
        if self.curriculum is not None and self.curriculum.mode != "fixed":
            raise ValueError(
                f"reset option difficulty: regimen {self.name!r} moves one difficulty for every env, so it "
                "takes one number, not one per env; regimen='pcg' takes a difficulty per env"
            )
        return self._checked_difficulty(number)

    def apply_options(self, options: ResetOptions, env_indices: Sequence[int]) -> None:
        """The checked options on the envs ``env_indices`` (those resetting): one difficulty
        moves every env's; a per-env difficulty or level is taken by each resetting env."""
        if isinstance(options.difficulty, float):
            self.set_difficulty(options.difficulty)
        elif options.difficulty is not None:
            for i in env_indices:
                self._env_difficulty[i] = options.difficulty[i]
        for i in env_indices if options.levels is not None else ():
            if options.levels[i] is not None:
                self.source.request([i], options.levels[i])


def _used_arguments(regimen: str, difficulty: float | None, alpha: float | None) -> tuple[float, float]:
    """``difficulty`` and ``alpha`` (``None``: not given) with their defaults; refused where the
    regimen would ignore them (DR draws each level's difficulty itself, a human level has none)."""
    unused = unused_arguments(regimen, difficulty=difficulty, alpha=alpha)
    if unused:
        arg = unused[0]
        raise ValueError(
            f"regimen {regimen!r} takes no {arg}= ({regimen_kind(regimen).summary}), so it would have "
            f"no effect; the regimens that take it: {', '.join(regimens_taking(arg))}"
        )
    return (0.0 if difficulty is None else float(difficulty), 0.01 if alpha is None else float(alpha))


@dataclass(frozen=True)
class ResetOptions:
    """The checked options of one reset: one difficulty for every env, or one per env; the level
    of each env for this episode (``None``: its regimen's)."""

    difficulty: float | tuple[float, ...] | None
    levels: tuple[Level | None, ...] | None


def _per_env(value: Any) -> bool:
    """Whether a reset option's value is a list of one per env (a list, tuple or array)."""
    return isinstance(value, list | tuple) or (isinstance(value, np.ndarray) and value.ndim > 0)


def _number(name: str, value: Any, num_envs: int) -> float:
    """A reset option's number, or one line saying what the option takes."""
    try:
        if isinstance(value, bool):
            raise TypeError
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(
            f"reset option {name}: expected a number in [0, 1] for every env, or a list of {num_envs} "
            f"numbers (one per env); got {type(value).__name__} {_shown(value)}"
        ) from None


def observation_space(game: str, obs: str) -> gym.spaces.Box:
    """One env's observation space: ``tiles`` ``[C, H, W]`` in {0, 1}, ``pixels`` ``[3, 10H, 10W]``."""
    checked_observation_kind(obs)
    rules = get_game(game)
    fmt = rules.level_format
    if obs == "tiles":
        return gym.spaces.Box(0, 1, (len(rules.tile_types), fmt.height, fmt.width), np.uint8)
    return gym.spaces.Box(0, 255, (3, fmt.height * CELL, fmt.width * CELL), np.uint8)


class GVGAIGymEnv(gym.Env):
    """One GVGAI game behind the Gymnasium API (``gymnasium.make("gvgai_pcg/Zelda-v0", ...)``).

    Args:
        game: ``zelda``, ``solarfox``, ``frogs`` or ``boulderdash``.
        regimen: where levels come from (see ``Regimen``); ``"human"`` by default.
        difficulty: the difficulty of generated levels (``pcg``), or where PPCG starts (0 if not
            given); a regimen that would ignore it (DR, human levels) refuses it.
        obs: ``"tiles"`` or ``"pixels"``.
        render_mode: ``"rgb_array"`` (``[10H, 10W, 3]`` uint8), ``"ansi"`` (text) or ``"human"``
            (the text frame printed to stdout after every reset and step).
        level: the level(s) of the ``lv`` regimen.
        max_steps: the step limit that truncates an episode (2000, as in the study).
        alpha: the PPCG step per finished episode (0.01 if not given; only PPCG takes it).
        win_rule: what counts as a PPCG win (``"game"`` or ``"study"``).
        device: where the engine runs; observations are always returned as NumPy arrays.
        levels: the set of the ``levels`` regimen: a folder of level files, or a list of files.
        num_levels: ``pcg``: a fixed set of this many generated levels (0: a new one each episode).
        start_seed: ``pcg`` with ``num_levels``: the seed of the set's first level.
    """

    metadata = {"render_modes": list(RENDER_MODES), "render_fps": 15}

    def __init__(
        self,
        game: str = "zelda",
        regimen: str = "human",
        difficulty: float | None = None,
        obs: str = "tiles",
        render_mode: str | None = None,
        level: LevelSpec | Sequence[LevelSpec] = 0,
        max_steps: int = 2000,
        alpha: float | None = None,
        win_rule: str = "game",
        device: str = "cpu",
        levels: LevelSetSpec | None = None,
        num_levels: int = 0,
        start_seed: int = 0,
    ) -> None:
        if render_mode is not None and render_mode not in RENDER_MODES:
            raise ValueError(
                f"unknown render mode {render_mode!r}; valid modes are: {', '.join(RENDER_MODES)}"
            )
        self.render_mode = render_mode
        self.regimen = Regimen(
            game, regimen, 1, level, difficulty, alpha, win_rule, levels, num_levels, start_seed
        )
        self.engine = GVGAIEnv(
            game,
            1,
            self.regimen.source,
            obs=obs,
            max_steps=max_steps,
            device=device,
            difficulty=self.regimen.difficulty,
        )
        self.obs_kind = obs
        self.observation_space = observation_space(game, obs)
        self.action_space = gym.spaces.Discrete(self.engine.game.num_actions)
        self.action_names = self.engine.game.actions
        self._ended: str | None = None  # "terminated" or "truncated" once the episode is over
        self._started = False

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start an episode. ``options``: ``level`` (a Level, name, path or human index, for this
        episode) and ``difficulty`` (for generated levels, from now on)."""
        checked = self.regimen.check_options(options)  # a bad option changes nothing
        super().reset(seed=seed)
        if seed is not None:
            self.engine.set_seed(seed)
        elif not self._started:
            self.engine.set_seed(int(self.np_random.integers(2**31)))
        self._started = True
        self.regimen.apply_options(checked, [0])
        mask = torch.ones(1, dtype=torch.bool)
        self.regimen.restart(mask)
        out = self.engine.reset(self.regimen.reset_tensordict(mask, self.engine.device))
        self._ended = None
        self._render_human()
        return self._obs(out), self._info(out)

    def step(self, action: int) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if not self._started:
            raise RuntimeError("call reset() before step()")
        if self._ended is not None:
            raise RuntimeError(
                f"the episode has ended ({self._ended}); call reset() before step() again "
                "(the vector env, gymnasium.make_vec, resets finished envs itself)"
            )
        if not self.action_space.contains(action):
            raise ValueError(f"invalid action {action!r}; valid actions are 0..{self.action_space.n - 1}")
        action_td = TensorDict(
            {"action": torch.tensor([int(action)], device=self.engine.device)},
            batch_size=[1],
            device=self.engine.device,
        )
        out = self.engine.step(action_td).get("next")
        terminated, truncated = bool(out["terminated"][0, 0]), bool(out["truncated"][0, 0])
        self.regimen.record(out, torch.tensor([terminated or truncated]))
        if terminated or truncated:
            self._ended = "terminated" if terminated else "truncated"
        self._render_human()
        return self._obs(out), float(out["reward"][0, 0]), terminated, truncated, self._info(out)

    def _obs(self, td: TensorDictBase) -> np.ndarray:
        return td[self.obs_kind][0].cpu().numpy()

    def _info(self, td: TensorDictBase) -> dict[str, Any]:
        level = self.engine.current_levels[0]
        return {
            "won": bool(td["won"][0, 0]),
            "score": float(td["score"][0, 0]),
            "difficulty": float(td["level_difficulty"][0, 0]),  # DR draws it per level
            "level_seed": int(td["level_seed"][0, 0]),
            "level_name": (level.name or "") if level is not None else "",
        }

    def render(self) -> np.ndarray | str | None:
        if self.render_mode == "rgb_array":
            return self.engine.render(0, "rgb_array")
        if self.render_mode == "ansi":
            return self.engine.render(0, "ansi") + "\n"
        return None

    def _render_human(self) -> None:
        if self.render_mode == "human":
            sys.stdout.write(self.engine.render(0, "ansi") + "\n\n")
            sys.stdout.flush()
