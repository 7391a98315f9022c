"""The level-file format of each game: which characters are legal, which place the avatar,
and the full grid size.

Kept free of torch so that parsing, generators and analysis can use it cheaply. The game
modules (``gvgai_pcg.games``) give each character its meaning; this table only has to agree
with them, which ``tests/games`` checks.
"""

from __future__ import annotations

from dataclasses import dataclass


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
    # What the game's win condition needs (gvgai/RULES.md): without it a level is lost or won
    # without play. Checked by ``gvgai_pcg.levels.winnable``, never by parsing.
    win_needs: tuple[WinNeed, ...] = ()


LEVEL_FORMATS: dict[str, LevelFormat] = {
    # Zelda: the door (g) opens with the key (+); no door left is a win at the first tick.
    "zelda": LevelFormat(
        "zelda",
        "w.A+g123",
        "A",
        height=9,
        width=13,
        win_needs=(WinNeed("+", 1, "key (+)"), WinNeed("g", 1, "goal (g)")),
    ),
    # Solarfox: won when no pill (blib b, powerblib p) is left.
    "solarfox": LevelFormat(
        "solarfox", "w+.bpA21", "A", height=11, width=10, win_needs=(WinNeed("bp", 1, "pill (b or p)"),)
    ),
    # Frogs: won when the goal (g) is reached; no goal left is a win at the first tick.
    "frogs": LevelFormat(
        "frogs", "w+.g0=1234BA-x_l", "AB", height=11, width=28, win_needs=(WinNeed("g", 1, "goal (g)"),)
    ),
    # Boulderdash: the exit (e) opens for an avatar holding 9 diamonds (x).
    "boulderdash": LevelFormat(
        "boulderdash",
        "w.-eoxcbA",
        "A",
        height=13,
        width=26,
        win_needs=(WinNeed("e", 1, "exit (e)"), WinNeed("x", 9, "diamonds (x)")),
    ),
}


def level_format(game: str) -> LevelFormat:
    """The format of ``game``; an unknown name is refused with the valid choices."""
    try:
        return LEVEL_FORMATS[game]
    except KeyError:
        raise ValueError(
            f"unknown game {game!r}; valid games are: {', '.join(sorted(LEVEL_FORMATS))}"
        ) from None
