"""What a generated level contains, counted from its text: the numbers GENERATORS.md states ranges
for (active size, enemies, gems, boulders, walls, pills, lane types). Used by the distribution
tests and for the tables in docs/generators.md."""

from __future__ import annotations

from gvgai_pcg.levels.level import Level

ZELDA_BORDER_WALLS = 2 * 13 + 2 * 7
FROGS_STREET, FROGS_WATER = set(".lx_-"), set("0=13")


def zelda_counts(level: Level) -> dict[str, int]:
    return {
        "interior_walls": level.count("w") - ZELDA_BORDER_WALLS,
        "enemies": sum(level.count(c) for c in "123"),
        "doors": level.count("g"),
        "keys": level.count("+"),
    }


def solarfox_counts(level: Level) -> dict[str, int]:
    return {
        "pills": level.count("b") + level.count("p"),
        "enemy_ground": level.count("."),
        "walls": level.count("w"),
    }


def frogs_counts(level: Level) -> dict[str, int]:
    """Active size and lane types; the goal and start rows are not counted as lanes."""
    rows = [row for row in level.rows if set(row) != {"w"}]
    columns = [c for c in range(level.width) if any(row[c] != "w" for row in rows)]
    lanes = rows[1:-1]
    street = sum(1 for row in lanes if set(row) & FROGS_STREET)
    water = sum(1 for row in lanes if set(row) & FROGS_WATER)
    span = columns[-1] - columns[0] + 1
    return {
        "width": span if street + water else span + 2,
        "height": len(rows) + 2,
        "street_lanes": street,
        "water_lanes": water,
        "grass_lanes": len(lanes) - street - water,
    }


def boulderdash_counts(level: Level) -> dict[str, int]:
    return {
        "gems": level.count("x"),
        "boulders": level.count("o"),
        "enemies": level.count("b") + level.count("c"),
        "background": level.count("-"),
    }


COUNTS = {
    "zelda": zelda_counts,
    "solarfox": solarfox_counts,
    "frogs": frogs_counts,
    "boulderdash": boulderdash_counts,
}


def level_counts(level: Level) -> dict[str, int]:
    """The per-game counts of ``level``."""
    return COUNTS[level.game](level)
