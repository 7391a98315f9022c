"""The level-file format of each game: which characters are legal, which place the avatar,
and the full grid size.

Kept free of torch so that parsing, generators and analysis can use it cheaply. The game
modules (``gvgai_pcg.games``) give each character its meaning; this table only has to agree
with them, which ``tests/games`` checks.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LevelFormat:
    """What a level file of one game may contain."""

    game: str
    chars: str  # every legal character, in legend order
    avatar_chars: str  # characters that place the avatar; a level has exactly one of them
    height: int  # full grid height in cells (rows); levels may be smaller, never larger
    width: int  # full grid width in cells (columns)


LEVEL_FORMATS: dict[str, LevelFormat] = {
    "zelda": LevelFormat("zelda", "w.A+g123", "A", height=9, width=13),
    "solarfox": LevelFormat("solarfox", "w+.bpA21", "A", height=11, width=10),
    "frogs": LevelFormat("frogs", "w+.g0=1234BA-x_l", "AB", height=11, width=28),
    "boulderdash": LevelFormat("boulderdash", "w.-eoxcbA", "A", height=13, width=26),
}


def level_format(game: str) -> LevelFormat:
    """The format of ``game``; an unknown name is refused with the valid choices."""
    try:
        return LEVEL_FORMATS[game]
    except KeyError:
        raise ValueError(
            f"unknown game {game!r}; valid games are: {', '.join(sorted(LEVEL_FORMATS))}"
        ) from None
