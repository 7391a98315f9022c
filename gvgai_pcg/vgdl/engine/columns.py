"""The columns a sprite of a class holds beyond its position, orientation, kind and ``alive``,
with the values a fresh sprite starts with.

A sprite made mid-game starts from its type's pristine template (RULES.md §1.2): ``lastmove`` 0,
the first-update flag set, its counters and resources at zero. A level's sprites start the same,
so ``layout`` builds its records and tables from here, and ``creation`` resets a slot from here
(a Missile table's ``born``, its list order, is set by each of them: ``layout``).
"""

from __future__ import annotations

from gvgai_pcg.games.geometry import NONE
from gvgai_pcg.vgdl.plan import Plan

# Classes whose first update does not move them (Java's ``isFirstTick``, passive movement).
FIRST_UPDATE_SKIP = frozenset({"Missile", "OngoingAvatar"})
# Classes that keep an age.
AGED = frozenset({"Flicker", "OrientedFlicker"})
# Effects that read or change a resource their first sprite holds.
RESOURCE_EFFECTS = frozenset({"changeResource", "spawnIfHasMore"})
# Table classes whose sprites keep an orientation of their own (they move along it).
ORIENTED_TABLES = frozenset({"Missile"})
# Classes that keep Java's ``lastmove`` (a cooldown gate: their own move, or a pull on a record).
COUNTING_MOVES = frozenset({"Missile", "MovingAvatar", "RandomNPC"})


def resource_column(resource: str) -> str:
    return f"resource_{resource}"


def fresh_columns(plan: Plan, names: tuple[str, ...]) -> dict[str, int | bool]:
    """The extra columns of a sprite of types ``names`` (a record, or a table group's kinds) and
    the value each has in a fresh sprite."""
    classes = {plan.types[name].java_class for name in names}
    values: dict[str, int | bool] = {}
    if classes & AGED:
        values["age"] = 0
    if classes & FIRST_UPDATE_SKIP:
        values["fresh"] = True
    if classes & COUNTING_MOVES:
        values["lastmove"] = 0
    if "SpawnPoint" in classes:  # what it made so far (Java's counter, against its total)
        values["spawned"] = 0
    if "RandomNPC" in classes:
        values.update({"counter": 0, "prev": NONE})
    for rule in plan.pairs:
        if rule.name in RESOURCE_EFFECTS and set(rule.firsts) & set(names):
            values[resource_column(str(rule.values["resource"]))] = 0
    for name in names:
        for resource in held_resources(plan, name):
            values[resource_column(resource)] = 0
    return values


def held_resources(plan: Plan, name: str) -> tuple[str, ...]:
    """The resource types a ``collectResource`` can give to sprites of type ``name``."""
    held = [rule.firsts for rule in plan.pairs if rule.name == "collectResource" and name in rule.seconds]
    return tuple(dict.fromkeys(resource for firsts in held for resource in firsts))


def held_columns(plan: Plan, name: str) -> tuple[str, ...]:
    """The resource types sprites of type ``name`` keep a count of: given by collectResource, or
    changed or read by a rule that names ``name`` as first."""
    changed = [
        str(rule.values["resource"])
        for rule in plan.pairs
        if rule.name in RESOURCE_EFFECTS and name in rule.firsts
    ]
    return tuple(dict.fromkeys([*held_resources(plan, name), *changed]))


def oriented_table(plan: Plan, names: tuple[str, ...]) -> bool:
    """Whether a table of ``names`` keeps each sprite's orientation."""
    return any(plan.types[name].java_class in ORIENTED_TABLES for name in names)
