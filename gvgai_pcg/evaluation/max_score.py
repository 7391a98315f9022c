"""The "Max" row: the highest score the rules allow, derived from each level, never typed in.

Each game owns its formula (``Game.max_score``, RULES.md §4.6, 5.8, 6.6, 7.6): Zelda
2·monsters + 2; Solarfox blibs + 2·powerblibs; Frogs 1 per goal; Boulderdash
2·min(10, diamonds + k) + k with k the butterflies when the level has a crab (0 without an exit).
A test set's Max is the mean over its levels.
"""

from __future__ import annotations

from collections.abc import Sequence

from gvgai_pcg.games import get_game
from gvgai_pcg.levels import Level


def level_max_score(level: Level) -> int:
    return int(get_game(level.game).max_score(level))


def mean_max_score(levels: Sequence[Level]) -> float:
    """The mean of the levels' maxima (a test set's cell in the Max row)."""
    if not levels:
        raise ValueError("mean_max_score needs at least one level")
    return sum(level_max_score(level) for level in levels) / len(levels)
