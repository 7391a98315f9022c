"""What a Solarfox level contains, and whether it is playable as the generator promises
(GENERATORS.md §1.3): counted and checked from its text."""

from __future__ import annotations

from gvgai_pcg.levels.level import Level


def counts(level: Level) -> dict[str, int]:
    return {
        "pills": level.count("b") + level.count("p"),
        "enemy_ground": level.count("."),
        "walls": level.count("w"),
    }


def playability_problems(level: Level) -> list[str]:
    """Side walls, one enemy in each of the top and bottom rows, at least one pill."""
    problems = []
    if any(row[0] != "w" or row[-1] != "w" for row in level.rows):
        problems.append("side columns are not walls")
    if level.rows[0].count("2") != 1 or level.rows[-1].count("1") != 1:
        problems.append("expected one top enemy '2' and one bottom enemy '1'")
    if level.count("b") + level.count("p") == 0:
        problems.append("no pills")
    return problems
