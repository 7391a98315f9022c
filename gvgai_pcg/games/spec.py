"""``GameSpec``: everything that makes one game, named in one place.

A game is one folder, ``gvgai_pcg/games/<name>/``: its rules (a ``Game`` subclass), its level
generator, its level format, the counts and checks of its generated levels, its human levels and
frozen test sets, and the constants the study keeps for it. The folder's ``__init__.py`` holds a
``GameSpec`` called ``SPEC`` that names all of these, and every table of the package (level
parsing, the generators, the analysis, the Gymnasium ids, the curriculum's win rule, the
benchmark) reads the spec through ``gvgai_pcg.games.registry``, never a list of games.

This module imports nothing of gvgai_pcg, so that parsing a level (``gvgai_pcg.levels``) can read
the format of its game without the engine: the spec names the rules and the generator by import
path (``"package.module:attribute"``), which the registry imports on first use. A game defined
outside a package may give the class and the function themselves.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from gvgai_pcg.levels.level import Level

Generator = Callable[[float, int], "Level"]
# ``edit(level, seed) -> Level``: a new level of the same game and size with one small random edit
# chosen by ``seed``, still valid for the game's format and checks (ACCEL's level editor).
Editor = Callable[["Level", int], "Level"]


@dataclass(frozen=True)
class WinNeed:
    """Something a level must hold to be winnable: at least ``count`` cells of ``chars``."""

    chars: str  # any of these characters counts
    count: int
    what: str  # how a person names it, e.g. "key (+)"


@dataclass(frozen=True)
class LevelFormat:
    """What a level file of one game may contain."""

    game: str
    chars: str  # every legal character, in legend order
    avatar_chars: str  # characters that place the avatar; a level has exactly one of them
    height: int  # full grid height in cells (rows); levels may be smaller, never larger
    width: int  # full grid width in cells (columns)
    # What the game's win condition needs (docs/spec/RULES.md): without it a level is lost or won
    # without play. Checked by ``gvgai_pcg.levels.winnable``, never by parsing.
    win_needs: tuple[WinNeed, ...] = ()


@dataclass(frozen=True)
class StepFacts:
    """What the engine needs to know of a game to choose how an env of it steps
    (``gvgai_pcg.engine.step_plan``), in one value; the default is a game that ticks eagerly.

    Every opt-out below a game sets says why where it sets it, with the command that reproduces
    it, so that it can be dropped once the compiler is fixed.

    Args:
        compiles: whether ``Game.tick`` traces as one graph (no data-dependent shapes or host
            syncs), so that the engine may run it compiled (``gvgai_pcg.engine.compiled``).
        eager_when: bool host arguments (``Game.host_arguments``) whose graph the compiler gets
            wrong, or runs slower than eager (measured): a tick where one is true runs eagerly.
        max_compiled_batch: the largest batch that steps compiled, where the compiled tick stops
            paying above it (measured); ``None``: no limit.
        parallel_graph: whether a large batch on several threads may tick through the graph whose
            loops over the envs run in parallel (``LARGE_BATCH_PER_THREAD``); off: a miscompile
            opt-out.
        compiled_devices: the device types whose compiled tick is held to the eager one; on any
            other the env steps eagerly.
    """

    compiles: bool = False
    eager_when: tuple[str, ...] = ()
    max_compiled_batch: int | None = None
    parallel_graph: bool = True
    compiled_devices: tuple[str, ...] = ("cpu", "cuda")


@dataclass(frozen=True)
class GameSpec:
    """One game: what it is called, where its parts are, and what the study keeps for it.

    Args:
        name: the registry key and the prefix of its level names (``zelda_lvl0``), lower case.
        title: the name as people write it (``"Boulderdash"``): figure titles and the Gymnasium
            id ``gvgai_pcg/<title>-v0``.
        level_format: the legend, avatar characters and full grid size of its levels.
        rules: the ``Game`` subclass, or its import path ``"package.module:Class"``.
        generator: ``generate(difficulty, seed) -> Level``, or its import path; registered as
            the generator named ``name``. ``None``: the game has no generator.
        editor: ``edit(level, seed) -> Level``, or its import path: one small random edit of a
            level that keeps it valid (ACCEL's editor, ``registry.level_editor``). ``None``: the
            game has no editor.
        counts: what a level contains (``{"keys": 1, ...}``), for the generator tests and docs.
        playability_problems: what keeps a generated level from being playable as the generator
            promises (an empty list when nothing does).
        study_tileset: the characters the study's PCA encodes, one channel each, in order;
            ``None``: every character of the legend but floor.
        study_score_win: the study's curriculum counts an episode with at least this score as a
            win (GENERATORS.md §2); ``None``: anything but a loss is a win.
        data_package: the package whose folder holds ``human_levels/<name>_lvl<i>.txt`` and
            ``test_sets/`` (a manifest and its level files); ``None``: no shipped levels.
        human_levels: how many human-designed levels ``human_levels/`` holds.
        human_level_files: instead of a data package, the path of the human level files with
            ``{index}`` in it (a GVGAI corpus game's levels, read from the folder the user names:
            ``gvgai_pcg.vgdl.corpus_games``); ``None``: they are in ``data_package``.
        study_index: the game's place in the study (0-3): the order of its tables and figures
            and the block of its frozen test-set seeds. ``None`` for a game outside the study.
        bench_target: the tiles steps/s at B = 4096 on 2 CPU cores that the benchmark holds the
            game to (what each game's port was asked to reach); ``None``: no target.
        frame_cost: the relative cost of a training frame, to share a sweep between jobs (the
            small sweep's run hours per game, Zelda = 1: docs/results.md, "Status").
        step_facts: whether and where its tick compiles, and its miscompile opt-outs
            (``StepFacts``); the default ticks eagerly.
    """

    name: str
    title: str
    level_format: LevelFormat
    rules: str | type
    generator: str | Generator | None = None
    editor: str | Editor | None = None
    counts: Callable[[Level], dict[str, int]] | None = None
    playability_problems: Callable[[Level], list[str]] | None = None
    study_tileset: str | None = None
    study_score_win: float | None = None
    data_package: str | None = None
    human_levels: int = 0
    human_level_files: str | None = None
    study_index: int | None = None
    bench_target: int | None = None
    frame_cost: float = 1.0
    step_facts: StepFacts = StepFacts()

    def __post_init__(self) -> None:
        if not self.name.isidentifier() or self.name != self.name.lower() or "_" in self.name:
            raise ValueError(
                f"game name {self.name!r}: use lower-case letters and digits (no '_', which separates "
                "a level name's parts, e.g. zelda_lvl0)"
            )
        if self.level_format.game != self.name:
            raise ValueError(
                f"game {self.name!r}: its level format says game {self.level_format.game!r}; "
                "the two names must agree"
            )
        if self.human_levels and self.data_package is None and self.human_level_files is None:
            raise ValueError(
                f"game {self.name!r} has {self.human_levels} human levels but no data_package "
                "or human_level_files"
            )


def load_object(reference: Any) -> Any:
    """``reference`` itself, or the object an import path ``"package.module:attribute"`` names."""
    if not isinstance(reference, str):
        return reference
    import importlib

    module_name, _, attribute = reference.partition(":")
    if not attribute:
        raise ValueError(f"{reference!r} is not an import path of the form 'package.module:attribute'")
    return getattr(importlib.import_module(module_name), attribute)
