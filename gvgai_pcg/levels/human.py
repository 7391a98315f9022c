"""The 20 human-designed levels of the study, shipped as package data (see ``data/NOTICE``)."""

from __future__ import annotations

from functools import cache
from importlib.resources import files

from gvgai_pcg.levels.formats import LEVEL_FORMATS, level_format
from gvgai_pcg.levels.level import Level

HUMAN_LEVEL_COUNT = 5


@cache
def human_level(game: str, index: int) -> Level:
    """Human level ``index`` (0-4) of ``game``, e.g. ``human_level("zelda", 0)``."""
    level_format(game)  # refuses unknown games with the valid choices
    if not 0 <= index < HUMAN_LEVEL_COUNT:
        raise ValueError(f"human level index must be 0..{HUMAN_LEVEL_COUNT - 1}, got {index}")
    name = f"{game}_lvl{index}"
    text = files("gvgai_pcg.levels").joinpath("data", f"{name}.txt").read_text()
    return Level.parse(text, game, source=f"gvgai_pcg/levels/data/{name}.txt", name=name)


def human_levels(game: str) -> list[Level]:
    """All five human levels of ``game``, in index order."""
    return [human_level(game, i) for i in range(HUMAN_LEVEL_COUNT)]


def resolve_level(spec: str, game: str | None = None) -> Level:
    """A level from a name (``zelda_lvl3``) or a file path; with ``game``, one whose name says it
    belongs to another game is refused (its characters may well parse as this game's)."""
    from pathlib import Path

    if game is not None:
        check_named_game(Path(spec).stem, game)
    stem = spec.rsplit("_lvl", 1)
    if len(stem) == 2 and stem[1].isdigit() and not Path(spec).exists():
        return human_level(stem[0], int(stem[1]))
    return Level.load(spec, game)


def check_named_game(name: str, game: str) -> None:
    """Refuse a level named after another game (``boulderdash_lvl0``, ``frogs_d0.5_s3``)."""
    for other in LEVEL_FORMATS:
        if other != game and name.startswith(f"{other}_"):
            raise ValueError(f"{name} is named as a {other} level, not a {game} one")
