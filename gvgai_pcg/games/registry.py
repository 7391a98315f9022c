"""The game registry: names to ``Game`` instances, with a clear error for unknown names."""

from __future__ import annotations

from collections.abc import Callable

from gvgai_pcg.games.base import Game

_GAMES: dict[str, Game] = {}


def register_game(name: str) -> Callable[[type[Game]], type[Game]]:
    """Class decorator: make ``cls()`` available as ``get_game(name)``."""

    def decorate(cls: type[Game]) -> type[Game]:
        if name in _GAMES:
            raise ValueError(f"game {name!r} is already registered")
        cls.name = name
        _GAMES[name] = cls()
        return cls

    return decorate


def get_game(name: str) -> Game:
    """The registered game called ``name``."""
    try:
        return _GAMES[name]
    except KeyError:
        raise ValueError(
            f"unknown game {name!r}; registered games are: {', '.join(sorted(_GAMES))}"
        ) from None


def registered_games() -> list[str]:
    return sorted(_GAMES)
