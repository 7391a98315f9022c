"""Levels as binary feature vectors, the way the study's PCA notebook encodes them (GENERATORS.md §5).

A level becomes a ``[T, H, W]`` 0/1 array at the game's full size: channel ``t`` is 1 where the
cell holds ``tileset[t]``. Floor (``.``) is never encoded, and characters outside the tileset are
dropped (all-zero), as in the study. Its tilesets (each game's ``GameSpec.study_tileset``) leave
out some sprite types (Boulderdash's avatar, Frogs' ``_`` and ``B``); ``complete=True`` encodes
every character of the game's legend except floor instead. Smaller levels are padded with wall
at the bottom and right first, the study's padding of human Frogs level 4, so every vector of a
game has the same length.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from gvgai_pcg.games.registry import get_game_spec
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.padding import pad_rows

FLOOR = "."
PAD = "w"


def tileset(game: str, complete: bool = False) -> str:
    """The characters encoded for ``game``, one channel each, in channel order: the study's
    tileset (``GameSpec.study_tileset``), or with ``complete`` (or for a game that names none)
    every character of its legend but floor."""
    spec = get_game_spec(game)
    if complete or spec.study_tileset is None:
        return "".join(ch for ch in spec.level_format.chars if ch != FLOOR)
    return spec.study_tileset


def padded_rows(level: Level) -> list[str]:
    """``level``'s rows grown to the game's full size with wall rows/columns at the bottom and right."""
    fmt = level.format
    return pad_rows(level.rows, fmt.height, fmt.width, PAD, f"{level.name or ''} of {level.game}")


def encode_level(level: Level, complete: bool = False) -> np.ndarray:
    """``[T, H, W]`` uint8 one-hot of ``level`` at full size (T = ``len(tileset(game, complete))``)."""
    chars = np.array([list(row) for row in padded_rows(level)])
    tiles = np.array(list(tileset(level.game, complete)))
    return (chars[None, :, :] == tiles[:, None, None]).astype(np.uint8)


def encode_levels(levels: Sequence[Level], complete: bool = False) -> np.ndarray:
    """``[N, T*H*W]`` uint8 flattened encodings of levels of one game."""
    games = {level.game for level in levels}
    if len(games) != 1:
        raise ValueError(f"encode_levels needs levels of exactly one game, got {sorted(games)}")
    return np.stack([encode_level(level, complete).reshape(-1) for level in levels])
