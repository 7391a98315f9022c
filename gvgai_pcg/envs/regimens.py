"""The training regimens: one table for training (``gvgai_pcg.rl.environment``) and for the
Gymnasium API (``gvgai_pcg.envs.gym_adapter``), so both accept the same names and build the same
level source and curriculum from them.

A regimen says where a resetting env takes its next level from: levels that are given (one human
level, human levels 0-3, all five, a level set of your own) or generated levels, at a fixed
difficulty (PCG X) or one that moves with the agent's wins and losses (Progressive PCG).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from gvgai_pcg.envs.difficulty import DifficultyTransform
from gvgai_pcg.envs.level_sources import GeneratedLevels, GeneratedLevelSet, LevelSource, as_level_source
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.winnable import warn_unwinnable


@dataclass(frozen=True)
class RegimenKind:
    name: str
    generated: bool  # generated levels (a difficulty applies) rather than given ones
    summary: str


REGIMENS: dict[str, RegimenKind] = {
    kind.name: kind
    for kind in (
        RegimenKind("lv", False, "Lv X: every episode on one given level"),
        RegimenKind("lv0-3", False, "Lv 0-3: a uniformly drawn human level among 0-3"),
        RegimenKind("human", False, "all five human levels, uniformly"),
        RegimenKind("levels", False, "a level set of your own, uniformly"),
        RegimenKind("pcg", True, "PCG X: generated levels at the fixed difficulty X"),
        RegimenKind("ppcg", True, "Progressive PCG: generated levels at a difficulty that follows wins"),
    )
}
GIVEN_REGIMENS = tuple(name for name, kind in REGIMENS.items() if not kind.generated)
GENERATED_REGIMENS = tuple(name for name, kind in REGIMENS.items() if kind.generated)


def regimen_kind(name: str) -> RegimenKind:
    """The regimen called ``name``; an unknown name is refused with the valid ones."""
    try:
        return REGIMENS[name]
    except KeyError:
        raise ValueError(f"unknown regimen {name!r}; valid regimens are: {', '.join(REGIMENS)}") from None


def regimen_source(
    game: str,
    name: str,
    given: Sequence[Level] | None = None,
    difficulty: float = 0.0,
    num_levels: int = 0,
    start_seed: int = 0,
    generator: str | None = None,
) -> LevelSource:
    """The level source of regimen ``name``: the ``given`` levels (one: every episode; more: one
    drawn uniformly), named in a warning where one cannot be won; or generated levels, a new one
    every episode or, with ``num_levels`` >= 1 (PCG X only), a fixed set from ``start_seed``, made
    by ``generator`` (any registered generator of the game's levels; default: the game's own)."""
    kind = regimen_kind(name)
    if (num_levels or start_seed) and name != "pcg":
        raise ValueError(f"num_levels and start_seed are for regimen='pcg', not {name!r}")
    if kind.generated:
        if num_levels > 0:
            return GeneratedLevelSet(game, difficulty, num_levels, start_seed, generator)
        return GeneratedLevels(game, generator)
    if not given:
        raise ValueError(f"the regimen {name!r} plays given levels, and none were given")
    warn_unwinnable(given, "training")  # generated levels are tested to be winnable
    return as_level_source(game, list(given))


def regimen_curriculum(
    game: str, name: str, difficulty: float = 0.0, alpha: float = 0.01, win_rule: str = "game"
) -> DifficultyTransform | None:
    """The ``DifficultyTransform`` of a generated-level regimen (PCG X: fixed at ``difficulty``;
    PPCG: starts there and moves by ``alpha``), ``None`` for given levels."""
    if not regimen_kind(name).generated:
        return None
    mode = "progressive" if name == "ppcg" else "fixed"
    return DifficultyTransform(mode, alpha=alpha, start=difficulty, win_rule=win_rule, game=game)
