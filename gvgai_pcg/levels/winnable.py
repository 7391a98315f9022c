"""Whether a level holds what its game's win condition needs (``LevelFormat.win_needs``).

A level can parse and still be pointless to play: a Zelda level without a key runs to the step
limit every episode, one without a door is won at the first tick. Training and evaluation warn
about such a level once per process (a log record naming it), and play it all the same: a
designer may mean it, and the Boulderdash count ignores the diamonds that crabs make of
butterflies.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable

from gvgai_pcg.levels.formats import LEVEL_FORMATS
from gvgai_pcg.levels.level import Level

log = logging.getLogger(__name__)
SHOWN_NAMES = 10  # a warning about many levels names this many of them
_warned: set[Level] = set()


def missing_to_win(level: Level) -> list[str]:
    """What ``level`` lacks to be winnable, e.g. ``["a key (+): needs 1, has 0"]``; empty when
    nothing is missing (or the game declares no needs)."""
    fmt = LEVEL_FORMATS.get(level.game)
    problems = []
    for need in fmt.win_needs if fmt is not None else ():
        have = sum(level.count(char) for char in need.chars)
        if have < need.count:
            problems.append(f"{need.what}: needs {need.count}, has {have}")
    return problems


def describe(level: Level) -> str:
    return level.name or f"<unnamed {level.game} level>"


def warn_unwinnable(levels: Iterable[Level], use: str) -> list[Level]:
    """Log one warning for the levels among ``levels`` that cannot be won and were not warned
    about before in this process; ``use`` says where they go ("training", "evaluation").
    Returns the levels warned about now."""
    found: dict[Level, list[str]] = {}
    for level in levels:
        if level not in _warned and level not in found:
            problems = missing_to_win(level)
            if problems:
                found[level] = problems
    _warned.update(found)
    if len(found) == 1:
        level, problems = next(iter(found.items()))
        log.warning("%s level %s cannot be won (%s)", use, describe(level), "; ".join(problems))
    elif found:
        names = [describe(level) for level in found]
        shown = ", ".join(names[:SHOWN_NAMES]) + (
            f" and {len(names) - SHOWN_NAMES} more" if len(names) > SHOWN_NAMES else ""
        )
        first = "; ".join(next(iter(found.values())))
        log.warning("%d %s levels cannot be won: %s (the first: %s)", len(found), use, shown, first)
    return list(found)
