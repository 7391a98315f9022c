"""The level-file format of each game: which characters are legal, which place the avatar, and
the full grid size.

Each game states its own format in its folder (``GameSpec.level_format``); this module reads them
from the registry. Kept free of torch so that parsing, generators and analysis can use it
cheaply. The rules of a game give each character its meaning; its format only has to agree with
them, which ``tests/games`` checks.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

from gvgai_pcg.games.registry import find_game_spec, get_game_spec, registered_games
from gvgai_pcg.games.spec import LevelFormat, WinNeed

__all__ = ["LEVEL_FORMATS", "LevelFormat", "WinNeed", "level_format"]


class _LevelFormats(Mapping[str, LevelFormat]):
    """Game name -> ``LevelFormat`` of every registered game (a read-only view of the registry)."""

    def __getitem__(self, game: str) -> LevelFormat:
        spec = find_game_spec(game)
        if spec is None:
            raise KeyError(game)
        return spec.level_format

    def __iter__(self) -> Iterator[str]:
        return iter(registered_games())

    def __len__(self) -> int:
        return len(registered_games())

    def __repr__(self) -> str:
        return f"LEVEL_FORMATS({', '.join(registered_games())})"


LEVEL_FORMATS: Mapping[str, LevelFormat] = _LevelFormats()


def level_format(game: str) -> LevelFormat:
    """The format of ``game``; an unknown name is refused with the valid choices."""
    return get_game_spec(game).level_format
