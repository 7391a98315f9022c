"""One character per sprite type, so a level is readable as text in a terminal.

Types are drawn in the game's ``tile_types`` order with the avatar last, so the avatar is never
hidden by what it stands on. A type missing here is shown by its first letter.
"""

from __future__ import annotations

import numpy as np

AVATAR_TYPES = frozenset({"avatar", "nokey", "withkey"})
EMPTY = " "
GLYPHS = {
    # shared
    "wall": "#",
    "goal": "G",
    "sword": "/",
    "avatar": "A",
    "nokey": "A",
    "withkey": "A",
    # zelda
    "key": "+",
    "monsterQuick": "1",
    "monsterNormal": "2",
    "monsterSlow": "3",
    # solarfox
    "enemyground": ".",
    "blib": "b",
    "powerblib": "p",
    "powerblibturning": "p",
    "top": "E",
    "btm": "E",
    "upshot": "|",
    "downshot": "|",
    # frogs
    "water": "~",
    "forestDense": "T",
    "forestSparse": "t",
    "log": "=",
    "fastRtruck": ">",
    "slowRtruck": ">",
    "fastLtruck": "<",
    "slowLtruck": "<",
    # boulderdash
    "dirt": ".",
    "exitdoor": "E",
    "diamond": "x",
    "boulder": "o",
    "crab": "c",
    "butterfly": "b",
}


def glyph(type_name: str) -> str:
    return GLYPHS.get(type_name, type_name[0])


def text_rows(tile_types: tuple[str, ...], tiles: np.ndarray) -> list[str]:
    """The ``tiles`` observation (``[C, H, W]``, channel c = ``tile_types[c]``) as H strings."""
    _, height, width = tiles.shape
    grid = np.full((height, width), EMPTY, dtype="<U1")
    order = sorted(range(len(tile_types)), key=lambda c: tile_types[c] in AVATAR_TYPES)
    for channel in order:
        grid[tiles[channel] > 0] = glyph(tile_types[channel])
    return ["".join(row) for row in grid]
