"""The regimens of the study (Lv X, Lv 0-3, PCG X, PPCG), ``human``, ``levels`` and DR, as
registered curricula. Their config sections and level sources are the ones the study's runs
were made with: ``results/small/runs/*/config.yaml`` compose and build as before
(``tests/curricula/test_small_runs.py``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from gvgai_pcg.config_rules import (
    DIFFICULTY,
    HUMAN_LEVEL,
    WIN_RULES,
    ConfigError,
    Integer,
    LevelPaths,
    ListOf,
    Number,
    OneOf,
    Text,
    level_set_tag,
)
from gvgai_pcg.curricula.base import Curriculum
from gvgai_pcg.levels import human_level, human_levels
from gvgai_pcg.levels.seeds import TRAINING_SEED_SPACE
from gvgai_pcg.levels.sets import load_level_set
from gvgai_pcg.levels.winnable import warn_unwinnable


def given_level_source(name: str, game: str, given: list):
    """The source of a given-level regimen: one level every episode, or one of several drawn
    uniformly; a level that cannot be won is named in a warning."""
    # torch on first use only (here and below): a refused command line lists the registered
    # curricula, which loads this module, without importing torch
    from gvgai_pcg.envs.level_sources import as_level_source

    if not given:
        raise ValueError(f"the regimen {name!r} plays given levels, and none were given")
    warn_unwinnable(given, "training")  # generated levels are tested to be winnable
    return as_level_source(game, list(given))


class GivenLevels(Curriculum):
    """Levels that are given: one drawn uniformly every episode (one level: always that one)."""

    def levels(self, game: str, section: Mapping[str, Any]) -> list:
        raise NotImplementedError

    def make_source(self, game, section, state=None):
        return given_level_source(self.name, game, self.levels(game, section))

    def training_levels(self, game, section, limit=None):
        levels = self.levels(game, section)
        return levels if limit is None else levels[:limit]


class HumanLevel(GivenLevels):
    name, summary, label = "lv", "Lv X: every episode on one given level", "Lv {level}"
    schema = {"name": Text(), "level": HUMAN_LEVEL, "tag": Text(), "win_rule": OneOf(WIN_RULES)}

    def levels(self, game, section):
        return [human_level(game, int(section["level"]))]

    def human_levels_trained(self, section):
        return (f"lv{int(section['level'])}",)

    def row_label(self, section):
        return f"Lv {section.get('level', '')}"


class HumanLevels0To3(GivenLevels):
    name, summary, label = "lv0-3", "Lv 0-3: a uniformly drawn human level among 0-3", "Lv 0-3"
    schema = {
        "name": Text(),
        "levels": ListOf(HUMAN_LEVEL, unique=True),
        "tag": Text(),
        "win_rule": OneOf(WIN_RULES),
    }

    def levels(self, game, section):
        return [human_level(game, int(i)) for i in section["levels"]]

    def human_levels_trained(self, section):
        return tuple(f"lv{int(i)}" for i in section["levels"])


class AllHumanLevels(GivenLevels):
    name, summary, label = "human", "all five human levels, uniformly", "Lv 0-4"
    schema = {"name": Text(), "tag": Text(), "win_rule": OneOf(WIN_RULES)}

    def levels(self, game, section):
        return human_levels(game)

    def human_levels_trained(self, section):
        return tuple(f"lv{i}" for i in range(5))


class OwnLevels(GivenLevels):
    name, summary, label = "levels", "a level set of your own, uniformly", "Levels {set}"
    schema = {"name": Text(), "path": LevelPaths(), "tag": Text(), "win_rule": OneOf(WIN_RULES)}

    def check(self, section, config):
        try:
            load_level_set(config["game"]["name"], section["path"])
        except (ValueError, OSError) as error:
            path, message = section["path"], str(error)
            if isinstance(path, str):
                message = message.removeprefix(f"{path}: ")  # named once is enough
            shown = repr(path)
            raise ConfigError(f"regimen.path={shown}: {message}") from None

    def levels(self, game, section):
        return load_level_set(game, section["path"])

    def has_training_set(self, section):
        return True

    def row_label(self, section):
        return f"Levels {level_set_tag(section.get('path', ''))}"


class GeneratedCurriculum(Curriculum):
    """Generated levels at the difficulty a ``DifficultyTransform`` writes into each reset."""

    generated = True
    mode = "fixed"

    def start_difficulty(self, section: Mapping[str, Any]) -> float:
        return float(section.get("start", 0.0))

    def make_state(self, game, section):
        from gvgai_pcg.envs.difficulty import DifficultyTransform

        return DifficultyTransform(
            self.mode,
            alpha=float(section.get("alpha", 0.01)),
            start=self.start_difficulty(section),
            win_rule=section.get("win_rule", "game"),
            game=game,
        )

    def make_source(self, game, section, state=None):
        from gvgai_pcg.envs.level_sources import GeneratedLevels

        return GeneratedLevels(game)

    def wrap(self, env, state=None):
        from gvgai_pcg.envs.reset_rows import RowResetTransformedEnv

        return RowResetTransformedEnv(env, state)

    def episodes_ended(self, state, next_tensordict, finished):
        state.record(next_tensordict, finished)

    def settable_difficulty(self, state):
        return state


class FixedDifficulty(GeneratedCurriculum):
    name, summary = "pcg", "PCG X: generated levels at the fixed difficulty X"
    schema = {
        "name": Text(),
        "difficulty": DIFFICULTY,
        "num_levels": Integer(0, TRAINING_SEED_SPACE),
        "start_seed": Integer(0, TRAINING_SEED_SPACE - 1),
        "win_rule": OneOf(WIN_RULES),
        "tag": Text(),
    }

    def start_difficulty(self, section):
        return float(section["difficulty"])

    def check(self, section, config):
        count, start = section["num_levels"], section["start_seed"]
        if count == 0 and start != 0:
            raise ConfigError(
                f"regimen.start_seed={start}: expected 0 with regimen.num_levels=0 (unlimited levels); "
                "a start seed picks the first level of a finite set (regimen.num_levels >= 1)"
            )
        if start + count > TRAINING_SEED_SPACE:
            raise ConfigError(
                f"regimen.start_seed={start}: expected start_seed + num_levels <= 2**31 "
                f"(training seeds stay below 2**31), got {start + count}"
            )

    def make_source(self, game, section, state=None):
        from gvgai_pcg.envs.level_sources import GeneratedLevels, GeneratedLevelSet

        count = int(section.get("num_levels", 0))
        if count > 0:
            difficulty = float(section.get("difficulty", 0.0))
            return GeneratedLevelSet(game, difficulty, count, int(section.get("start_seed", 0)))
        return GeneratedLevels(game)

    def training_levels(self, game, section, limit=None):
        count = int(section.get("num_levels", 0))
        if count <= 0:
            return None
        return self.make_source(game, section).first(limit if limit is not None else count)

    def has_training_set(self, section):
        return int(section.get("num_levels", 0) or 0) > 0

    def row_label(self, section):
        label = f"PCG {float(section.get('difficulty', 0)):g}"
        count = int(section.get("num_levels", 0) or 0)
        return f"{label}, {count} level{'s' if count != 1 else ''}" if count else label


class ProgressivePCG(GeneratedCurriculum):
    name, summary, label = (
        "ppcg",
        "Progressive PCG: generated levels at a difficulty that follows wins",
        "PPCG",
    )
    mode = "progressive"
    schema = {
        "name": Text(),
        "alpha": Number(0.0, 1.0, low_open=True),
        "start": DIFFICULTY,
        "win_rule": OneOf(WIN_RULES),
        "tag": Text(),
    }


class DomainRandomisation(Curriculum):
    """DR: a fresh generated level every episode at a difficulty drawn uniformly from [0, 1] per
    env and episode (from the episode seed, so reproducible); the UED papers' baseline (Dennis et
    al. 2020, PAIRED; Jiang et al. 2021, robust PLR)."""

    name, summary, label = "dr", "DR: a new generated level every episode at d ~ U[0, 1]", "DR"
    generated = True
    schema = {"name": Text(), "win_rule": OneOf(WIN_RULES), "tag": Text()}

    def make_source(self, game, section, state=None):
        from gvgai_pcg.envs.level_sources import RandomDifficultyLevels

        return RandomDifficultyLevels(game)


BUILTIN_CURRICULA: tuple[Curriculum, ...] = (
    HumanLevel(),
    HumanLevels0To3(),
    AllHumanLevels(),
    OwnLevels(),
    FixedDifficulty(),
    ProgressivePCG(),
    DomainRandomisation(),
)
