"""What a Boulderdash level contains, and whether it is playable as the generator promises
(GENERATORS.md §1.5): counted and checked from its text."""

from __future__ import annotations

from gvgai_pcg.generators._common import reachable
from gvgai_pcg.levels.level import Level


def counts(level: Level) -> dict[str, int]:
    return {
        "gems": level.count("x"),
        "boulders": level.count("o"),
        "enemies": level.count("b") + level.count("c"),
        "background": level.count("-"),
    }


def playability_problems(level: Level) -> list[str]:
    """One exit; every gem and the exit reachable from the avatar around walls and boulders."""
    if level.count("e") != 1:
        return [f"expected one exit 'e', found {level.count('e')}"]
    area = reachable(level, level.find("A")[0], blocked="wo")
    lost = [cell for cell in level.find("x") + level.find("e") if cell not in area]
    return [f"gem or exit at (row, col) {cell} unreachable from the avatar" for cell in lost]
