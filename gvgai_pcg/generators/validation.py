"""Playability by construction, checked on a finished level (GENERATORS.md §1.2, §1.4, §1.5).

The generators guarantee these properties without checking them at the end (Zelda: the door and
key are reachable; Boulderdash: every gem and the exit are reachable; Frogs: goal and start rows
in place). Each game's checks (``GameSpec.playability_problems``, in its folder's ``checks``)
verify the output independently, for the tests and for anyone loading levels from elsewhere.
"""

from __future__ import annotations

from gvgai_pcg.games.registry import get_game_spec
from gvgai_pcg.levels.level import Level


def playability_problems(level: Level) -> list[str]:
    """What keeps ``level`` from being playable as its generator promises (empty: nothing)."""
    check = get_game_spec(level.game).playability_problems
    return [] if check is None else check(level)
