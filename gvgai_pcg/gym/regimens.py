"""The training regimens by name, for training (``gvgai_pcg.rl.environment``) and the
Gymnasium API (``gvgai_pcg.gym.adapter``): both ask the registered curriculum
(``gvgai_pcg.curricula``), so both accept the same names and build the same level source and
shared state from them.

A regimen says where a resetting env takes its next level from: levels that are given (one human
level, human levels 0-3, all five, a level set of your own) or generated levels, at a fixed
difficulty (PCG X), one that moves with the agent's wins and losses (Progressive PCG), one drawn
every episode (DR), or whatever a plug-in curriculum decides.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from gvgai_pcg.config_rules import config_root
from gvgai_pcg.curricula import Curriculum, get_curriculum, registered_curricula
from gvgai_pcg.curricula.base import CurriculumRun
from gvgai_pcg.curricula.builtin import given_level_source
from gvgai_pcg.envs.level_sources import LevelSource
from gvgai_pcg.levels import Level


def regimen_kind(name: str) -> Curriculum:
    """The curriculum called ``name`` (``.generated``, ``.summary``); an unknown name is refused
    with the valid ones."""
    return get_curriculum(name)


def regimen_names(generated: bool | None = None) -> tuple[str, ...]:
    """The registered regimens' names (only the generated-level or given-level ones, if asked)."""
    return tuple(
        name for name, c in registered_curricula().items() if generated is None or c.generated == generated
    )


def regimen_defaults(name: str) -> dict[str, Any]:
    """The keys of regimen ``name``'s yaml (``conf/regimen/<name>.yaml``, or a plug-in's
    ``Curriculum.config``) that are plain values: a plug-in's own keys (the toy curriculum's
    ``pool``) reach its source from the Gymnasium API too. Interpolated values (the run tag) are
    left out: they name runs, which the Gymnasium API has none of."""
    from omegaconf import OmegaConf

    curriculum = regimen_kind(name)
    path = (
        Path(curriculum.config)
        if curriculum.config is not None
        else config_root() / "regimen" / f"{name}.yaml"
    )
    if not path.is_file():
        return {}
    node = OmegaConf.to_container(OmegaConf.load(path), resolve=False)
    return {key: value for key, value in node.items() if not (isinstance(value, str) and "${" in value)}


def regimen_section(
    name: str,
    difficulty: float = 0.0,
    alpha: float = 0.01,
    num_levels: int = 0,
    start_seed: int = 0,
    **more: Any,
) -> dict[str, Any]:
    """The config section of regimen ``name`` from the Gymnasium API's arguments (``difficulty``
    is PCG X's difficulty and PPCG's start), over the regimen's own defaults."""
    if (num_levels or start_seed) and name != "pcg":
        raise ValueError(f"num_levels and start_seed are for regimen='pcg', not {name!r}")
    section = regimen_defaults(name)
    section.update({"name": name, "alpha": alpha, "start": difficulty, **more})
    if name == "pcg":
        section.update(difficulty=difficulty, num_levels=num_levels, start_seed=start_seed)
    return section


def unused_arguments(name: str, **given: Any) -> list[str]:
    """Those of the Gymnasium API's ``given`` arguments (``difficulty``, ``alpha``; ``None``: not
    given) that regimen ``name`` would ignore: its section has no key for them
    (``regimen_section`` puts ``difficulty`` in PCG X's ``difficulty``, else in ``start``)."""
    keys = {"difficulty": "difficulty" if name == "pcg" else "start", "alpha": "alpha"}
    schema = regimen_kind(name).schema
    return [arg for arg, value in given.items() if value is not None and keys[arg] not in schema]


def regimens_taking(argument: str) -> list[str]:
    """The registered regimens that use the Gymnasium API's ``argument`` (``difficulty``, ``alpha``)."""
    return [name for name in regimen_names() if not unused_arguments(name, **{argument: 0.0})]


def regimen_run(
    game: str,
    name: str,
    difficulty: float = 0.0,
    alpha: float = 0.01,
    win_rule: str = "game",
    num_levels: int = 0,
    start_seed: int = 0,
) -> CurriculumRun:
    """A run of regimen ``name`` (``Curriculum.start``) from the Gymnasium API's arguments: its
    shared state (PCG X and PPCG: their ``DifficultyTransform``, at ``difficulty`` and moving by
    ``alpha``), its source (PCG X with ``num_levels`` >= 1: a fixed set from ``start_seed``) and
    the route of its signals, as the trainer's run of the same section has them."""
    section = regimen_section(
        name, difficulty, alpha, num_levels=num_levels, start_seed=start_seed, win_rule=win_rule
    )
    return regimen_kind(name).start(game, section)


def given_source(game: str, name: str, given: Sequence[Level]) -> LevelSource:
    """The source of a regimen of given levels on the ``given`` ones (one: every episode; more:
    one drawn uniformly), named in a warning where one cannot be won."""
    return given_level_source(name, game, list(given))
