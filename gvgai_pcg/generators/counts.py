"""What a generated level contains, counted from its text: the numbers GENERATORS.md states ranges
for (active size, enemies, gems, boulders, walls, pills, lane types), and Frogs' logs and vehicles.
Each game counts its own (``GameSpec.counts``, in its folder's ``checks``); used by the
distribution tests, the tables in docs/generators.md, and the curricula page's table of the levels
each curriculum holds."""

from __future__ import annotations

from gvgai_pcg.games.registry import get_game_spec
from gvgai_pcg.levels.level import Level


def level_counts(level: Level) -> dict[str, int]:
    """The per-game counts of ``level``."""
    spec = get_game_spec(level.game)
    if spec.counts is None:
        raise ValueError(f"game {level.game!r} declares no level counts (GameSpec.counts)")
    return spec.counts(level)
