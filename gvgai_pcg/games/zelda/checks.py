"""What a Zelda level contains, and whether it is playable as the generator promises
(GENERATORS.md §1.2): counted and checked from its text."""

from __future__ import annotations

from gvgai_pcg.generators._common import reachable
from gvgai_pcg.levels.level import Level

BORDER_WALLS = 2 * 13 + 2 * 7


def counts(level: Level) -> dict[str, int]:
    return {
        "interior_walls": level.count("w") - BORDER_WALLS,
        "enemies": sum(level.count(c) for c in "123"),
        "doors": level.count("g"),
        "keys": level.count("+"),
    }


def playability_problems(level: Level) -> list[str]:
    """Exactly one door and key, both reachable from the avatar around walls."""
    problems = [f"expected one {c!r}, found {level.count(c)}" for c in "Ag+" if level.count(c) != 1]
    if problems:
        return problems
    area = reachable(level, level.find("A")[0], blocked="w")
    return [
        f"{name} unreachable from the avatar"
        for name, c in (("door", "g"), ("key", "+"))
        if level.find(c)[0] not in area
    ]
