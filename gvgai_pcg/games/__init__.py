"""The games: one folder per game (``zelda/``, ``solarfox/``, ...) and the registry that finds them.

A game folder holds everything that is that game (its rules, generator, level format, checks,
human levels and frozen test sets) and names them in one ``GameSpec``; ``registry`` maps names
to specs. The engine kit every game builds on lives beside the folders: ``base`` (the ``Game``
contract), ``geometry``, ``rules``, ``rng`` and ``render``.

This package imports no game and no torch: ``Game`` and the layer classes are loaded on first
access, the rules of a game when ``get_game`` first asks for them.
"""

from __future__ import annotations

import importlib
from typing import Any

from gvgai_pcg.games.registry import (
    get_game,
    get_game_spec,
    register_game,
    register_game_spec,
    registered_games,
    study_games,
)
from gvgai_pcg.games.spec import GameSpec, LevelFormat, StepFacts, WinNeed

_FROM_BASE = ("Game", "GridLayer", "SpriteArt", "SpriteLayer")

__all__ = [
    *_FROM_BASE,
    "GameSpec",
    "LevelFormat",
    "StepFacts",
    "WinNeed",
    "get_game",
    "get_game_spec",
    "register_game",
    "register_game_spec",
    "registered_games",
    "study_games",
]


def __getattr__(name: str) -> Any:
    if name in _FROM_BASE:
        return getattr(importlib.import_module("gvgai_pcg.games.base"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
