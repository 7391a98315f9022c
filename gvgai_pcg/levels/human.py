"""The human-designed levels of each game (the study's 20), shipped as package data in each game's
folder (``gvgai_pcg/games/<game>/human_levels/``; see ``gvgai_pcg/games/NOTICE``); a GVGAI corpus
game's are read from the folder that holds its VGDL file (``GameSpec.human_level_files``)."""

from __future__ import annotations

from functools import cache
from importlib.resources import files
from pathlib import Path

from gvgai_pcg.games.registry import get_game_spec, registered_games
from gvgai_pcg.levels.level import Level, decode

HUMAN_LEVELS_FOLDER = "human_levels"  # in a game's data package


@cache
def human_level(game: str, index: int) -> Level:
    """Human level ``index`` (0-4) of ``game``, e.g. ``human_level("zelda", 0)``."""
    spec = get_game_spec(game)  # refuses unknown games with the valid choices
    if spec.human_levels == 0 or (spec.data_package is None and spec.human_level_files is None):
        raise ValueError(f"game {game!r} ships no human levels")
    if not 0 <= index < spec.human_levels:
        raise ValueError(f"human level index must be 0..{spec.human_levels - 1}, got {index}")
    name = f"{game}_lvl{index}"
    if spec.human_level_files is not None:
        path = Path(spec.human_level_files.format(index=index))
        try:
            data = path.read_bytes()
        except OSError as error:
            raise ValueError(f"cannot read {game}'s human level {path}: {error.strerror}") from None
        return Level.parse(decode(data, str(path)), game, source=str(path), name=name)
    text = files(spec.data_package).joinpath(HUMAN_LEVELS_FOLDER, f"{name}.txt").read_text()
    source = f"{spec.data_package.replace('.', '/')}/{HUMAN_LEVELS_FOLDER}/{name}.txt"
    return Level.parse(text, game, source=source, name=name)


def human_levels(game: str) -> list[Level]:
    """All human levels of ``game`` (five for each game of the study), in index order."""
    return [human_level(game, i) for i in range(get_game_spec(game).human_levels)]


def resolve_level(spec: str, game: str | None = None) -> Level:
    """A level from a name (``zelda_lvl3``) or a file path; with ``game``, one whose name says it
    belongs to another game is refused (its characters may well parse as this game's)."""
    from pathlib import Path

    if game is not None:
        check_named_game(Path(spec).stem, game)
    stem = spec.rsplit("_lvl", 1)
    if len(stem) == 2 and stem[1].isdigit() and not Path(spec).exists():
        return human_level(stem[0], int(stem[1]))
    if not Path(spec).exists():
        named = f"{game}_lvl0 .. {game}_lvl4" if game else "zelda_lvl0 and the like"
        raise FileNotFoundError(
            f"{spec!r}: no such level; expected a human level's name ({named}) or a level file"
        )
    return Level.load(spec, game)


def check_named_game(name: str, game: str) -> None:
    """Refuse a level named after another game (``boulderdash_lvl0``, ``frogs_d0.5_s3``)."""
    for other in registered_games():
        if other != game and name.startswith(f"{other}_"):
            raise ValueError(f"{name} is named as a {other} level, not a {game} one")
