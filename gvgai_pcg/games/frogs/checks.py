"""What a Frogs level contains, and whether it is playable as the generator promises
(GENERATORS.md §1.4): counted and checked from its text."""

from __future__ import annotations

from gvgai_pcg.levels.level import Level

STREET, WATER = set(".lx_-"), set("0=13")
VEHICLES = "xl_-"


def counts(level: Level) -> dict[str, int]:
    """Active size and lane types (the goal and start rows are not counted as lanes), and the
    logs and vehicles in them (what ACCEL's editor adds and removes; a frog that starts on a log,
    B, counts as a log)."""
    rows = [row for row in level.rows if set(row) != {"w"}]
    columns = [c for c in range(level.width) if any(row[c] != "w" for row in rows)]
    lanes = rows[1:-1]
    street = sum(1 for row in lanes if set(row) & STREET)
    water = sum(1 for row in lanes if set(row) & WATER)
    span = columns[-1] - columns[0] + 1
    return {
        "width": span if street + water else span + 2,
        "height": len(rows) + 2,
        "street_lanes": street,
        "water_lanes": water,
        "grass_lanes": len(lanes) - street - water,
        "logs": level.count("=") + level.count("B"),
        "vehicles": sum(level.count(c) for c in VEHICLES),
    }


def playability_problems(level: Level) -> list[str]:
    """Goal row on top (goal walled on both sides), start row at the bottom, wall lines around."""
    goal_rows = [r for r, row in enumerate(level.rows) if "g" in row]
    if len(goal_rows) != 1 or level.count("g") != 1:
        return [f"expected one goal 'g', found {level.count('g')}"]
    top = goal_rows[0]
    bottom = (level.find("A") or level.find("B"))[0][0]  # B: a frog that starts on a log (human level 4)
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
