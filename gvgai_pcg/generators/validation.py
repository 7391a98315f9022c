"""Playability by construction, checked on a finished level (GENERATORS.md §1.2, §1.4, §1.5).

The generators guarantee these properties without checking them at the end (Zelda: the door and
key are reachable; Boulderdash: every gem and the exit are reachable; Frogs: goal and start rows
in place). These functions check the output independently, for the tests and for anyone loading
levels from elsewhere. Each returns a list of problems, empty when the level is fine.
"""

from __future__ import annotations

from collections.abc import Callable

from gvgai_pcg.levels.level import Level


def reachable(level: Level, start: tuple[int, int], blocked: str) -> set[tuple[int, int]]:
    """Cells 4-connected to ``start`` through cells whose character is not in ``blocked``."""
    rows = level.rows
    seen = {start}
    stack = [start]
    while stack:
        r, c = stack.pop()
        for nr, nc in ((r - 1, c), (r + 1, c), (r, c - 1), (r, c + 1)):
            if (
                0 <= nr < len(rows)
                and 0 <= nc < len(rows[0])
                and (nr, nc) not in seen
                and rows[nr][nc] not in blocked
            ):
                seen.add((nr, nc))
                stack.append((nr, nc))
    return seen


def zelda_problems(level: Level) -> list[str]:
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


def boulderdash_problems(level: Level) -> list[str]:
    """One exit; every gem and the exit reachable from the avatar around walls and boulders."""
    if level.count("e") != 1:
        return [f"expected one exit 'e', found {level.count('e')}"]
    area = reachable(level, level.find("A")[0], blocked="wo")
    lost = [cell for cell in level.find("x") + level.find("e") if cell not in area]
    return [f"gem or exit at (row, col) {cell} unreachable from the avatar" for cell in lost]


def frogs_problems(level: Level) -> list[str]:
    """Goal row on top (goal walled on both sides), start row at the bottom, wall lines around."""
    goal_rows = [r for r, row in enumerate(level.rows) if "g" in row]
    if len(goal_rows) != 1 or level.count("g") != 1:
        return [f"expected one goal 'g', found {level.count('g')}"]
    top = goal_rows[0]
    bottom = level.find("A")[0][0]
    rows = level.rows
    problems = []
    goal = rows[top].index("g")
    if rows[top][goal - 1] != "w" or rows[top][goal + 1] != "w":
        problems.append("the goal is not walled on both sides")
    if set(rows[top]) - set("w+g"):
        problems.append("the goal row is not grass")
    if set(rows[bottom]) - set("w+A"):
        problems.append("the start row is not grass")
    if bottom <= top:
        problems.append("the start row is not below the goal row")
    if set(rows[top - 1]) != {"w"} or set(rows[bottom + 1]) != {"w"}:
        problems.append("no wall line above the goal row and below the start row")
    if any(set(row) == {"w"} for row in rows[top : bottom + 1]):
        problems.append("a full wall line between the goal and start rows")
    return problems


def solarfox_problems(level: Level) -> list[str]:
    """Side walls, one enemy in each of the top and bottom rows, at least one pill."""
    problems = []
    if any(row[0] != "w" or row[-1] != "w" for row in level.rows):
        problems.append("side columns are not walls")
    if level.rows[0].count("2") != 1 or level.rows[-1].count("1") != 1:
        problems.append("expected one top enemy '2' and one bottom enemy '1'")
    if level.count("b") + level.count("p") == 0:
        problems.append("no pills")
    return problems


PROBLEMS: dict[str, Callable[[Level], list[str]]] = {
    "zelda": zelda_problems,
    "solarfox": solarfox_problems,
    "frogs": frogs_problems,
    "boulderdash": boulderdash_problems,
}


def playability_problems(level: Level) -> list[str]:
    """What keeps ``level`` from being playable as its generator promises (empty: nothing)."""
    return PROBLEMS[level.game](level)
