"""How each sprite type is held in a batched state, decided from the description alone.

The choices speak the hand-written engines' language (``games/base.py``):

- ``grid``: a ``[B, H, W]`` count grid, for a type whose sprites never move, carry no state of
  their own (no resources, health, age or spawn counter) and always sit on whole cells; two
  sprites in one cell are a count of 2 (Boulderdash's diamonds);
- ``record``: a ``[B]`` record with a presence flag, for an avatar type and a type Java keeps
  to one sprite (``singleton=True`` on its own line): Java refuses a second singleton, while a
  second avatar of one type is an overflow error like a full table's;
- ``table``: a ``[B, K]`` table of pixel positions, in Java's list order (level sprites row
  by row, then creation order), for the rest. ``K`` is fixed when a batch is compiled; a
  creation that finds no free slot is an overflow error, never a silent drop.

A type is *aligned* when its sprites are on whole cells at every tick: those can use the fast
cell-indexed path. It holds unless the type moves by a step that is not a whole cell
(``(int)(speed * 10)`` px in learning mode), is created where an unaligned sprite is, is pushed
or pulled by a type whose speed is not a whole cell (``bounceForward``, ``pullWithIt`` move by
the second's speed), or is put where an unaligned sprite is (``align``, ``teleportToExit``):
a fixed point over the types.

A table's capacity is a formula over a level (``Capacity``): its own count in the level, plus
what creations can add where they are bounded (a transform uses up its source, a spawn point
with ``total`` makes that many), else one slot for every cell of the level.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from gvgai_pcg.vgdl.java_classes import Const
from gvgai_pcg.vgdl.kinds import CREATING_EFFECTS, created_types, leaves
from gvgai_pcg.vgdl.model import Effect, GameDescription, SpriteType
from gvgai_pcg.vgdl.support import STILL_CLASSES

CELL = 10  # px: Java's learning mode forces 10-px cells
GRID, RECORD, TABLE = "grid", "record", "table"
# Classes that keep a state per sprite even when still: an age, a spawn counter.
TIMED_CLASSES = frozenset({"Flicker", "OrientedFlicker", "Spreader"})
# Classes that create sprites of their ``stype`` where they are (ShootAvatar one cell ahead).
PRODUCER_CLASSES = frozenset(
    {"SpawnPoint", "Bomber", "RandomBomber", "BomberRandomMissile", "ShootAvatar", "FlakAvatar", "Spreader"}
)
# Effects that move or turn their first sprite, and the one that gives it to its second.
MOVING_EFFECTS = frozenset(
    {
        "bounceForward",
        "pullWithIt",
        "wrapAround",
        "teleportToExit",
        "align",
        "attractGaze",
        "turnAround",
        "flipDirection",
        "reverseDirection",
        "bounceDirection",
        "wallBounce",
        "wallStop",
        "windGust",
        "slipForward",
    }
)
# Moving effects whose first moves by ``(int)(second.speed * 10)`` px (Java's BounceForward,
# PullWithIt), and those that put it where the second (teleportToExit: a portal's exit) is.
PUSHING_EFFECTS = frozenset({"bounceForward", "pullWithIt"})
FOLLOWING_EFFECTS = frozenset({"align", "teleportToExit", "windGust", "slipForward"})
# Moving effects that leave the first's orientation as it was.
KEEP_ORIENTATION = frozenset({"pullWithIt", "wrapAround", "reverseDirection"})
AXES = ("x", "y")
# Effects that change a resource or health count their first or second sprite holds (the
# effects that only read one need no state where nothing changes it).
FIRST_STATE_EFFECTS = frozenset(
    {"changeResource", "addHealthPoints", "addHealthPointsToMax", "subtractHealthPoints"}
)
SECOND_STATE_EFFECTS = frozenset({"collectResource", "collectResourceIfHeld"})
# Beyond what a level holds, a table with no creation bound gets this many slots a level cell.
HEADROOM_PER_CELL = 1


@dataclass(frozen=True)
class Capacity:
    """Slots a table needs for one level: ``constant`` + the level's count of each of
    ``level_types`` (a type may appear more than once, multiplied) + ``per_cell`` slots for every
    cell of the level."""

    level_types: tuple[str, ...]
    constant: int
    per_cell: int
    why: str

    def slots(self, counts: Mapping[str, int], cells: int) -> int:
        return self.constant + sum(counts.get(name, 0) for name in self.level_types) + self.per_cell * cells

    def formula(self) -> str:
        terms = [f"level {name}" for name in dict.fromkeys(self.level_types)]
        terms = [
            f"{self.level_types.count(name)} x {term}" if self.level_types.count(name) > 1 else term
            for name, term in zip(dict.fromkeys(self.level_types), terms, strict=True)
        ]
        if self.constant:
            terms.append(str(self.constant))
        if self.per_cell:
            terms.append(f"{self.per_cell} x cells" if self.per_cell > 1 else "cells")
        return " + ".join(terms) or "0"


@dataclass(frozen=True)
class Creation:
    """One way a sprite of a type appears during play: ``source``'s sprites make it, by
    ``how`` (an effect's name, or the source's class), at ``line``."""

    source: str
    how: str
    line: int
    bounded_by: int | None  # sprites one source sprite can make in a whole episode; None: no bound


def speed_px(sprite: SpriteType) -> int:
    """Pixels a move of this type covers: Java's ``(int)(speed * cell)``; 0 for still classes."""
    return 0 if sprite.java_class in STILL_CLASSES else push_px(sprite)


def push_px(sprite: SpriteType) -> int:
    """Pixels this type's speed moves a sprite it pushes or pulls, whatever its class."""
    speed = sprite.value("speed")
    return int(float(speed) * CELL) if isinstance(speed, int | float) else 0


def is_avatar(sprite: SpriteType) -> bool:
    return bool(sprite.java_class and sprite.java_class.endswith("Avatar"))


def creations(game: GameDescription) -> dict[str, list[Creation]]:
    """Every leaf type's ways to appear during play, in declaration order."""
    found: dict[str, list[Creation]] = {}
    for name in game.sprite_order:
        sprite = game.types[name]
        stype = sprite.value("stype") if sprite.java_class in PRODUCER_CLASSES else None
        if isinstance(stype, str) and stype in game.types:
            total = sprite.value("total")
            bound = (
                int(total)
                if sprite.java_class == "SpawnPoint" and isinstance(total, int) and total > 0
                else None
            )
            for made in leaves(game, stype):
                found.setdefault(made, []).append(Creation(name, str(sprite.java_class), sprite.line, bound))
    for effect in game.effects:
        if effect.name not in CREATING_EFFECTS:
            continue
        # A transform kills its first: one source sprite makes one sprite at most.
        bound = 1 if effect.name.startswith("transform") else None
        for made in created_types(game, effect):
            for source in leaves(game, effect.first):
                found.setdefault(made, []).append(Creation(source, effect.name, effect.line, bound))
    return found


def movers(game: GameDescription) -> dict[str, list[tuple[Effect, str]]]:
    """Per leaf type, the (effect, second type) rules that move or turn it."""
    found: dict[str, list[tuple[Effect, str]]] = {}
    for effect in game.effects:
        if effect.name not in MOVING_EFFECTS:
            continue
        for second in effect.seconds:
            target = second
            if effect.name == "teleportToExit":  # to the exit of the portal it touched
                portal = game.types.get(second)
                exit_type = portal.value("stype") if portal is not None else None
                target = exit_type if isinstance(exit_type, str) else second
            for first in leaves(game, effect.first):
                found.setdefault(first, []).append((effect, target))
    return found


def stateful(game: GameDescription) -> dict[str, str]:
    """Leaf types whose sprites hold a state of their own, with the reason."""
    found: dict[str, str] = {}
    made = creations(game)
    for name in game.sprite_order:
        sprite = game.types[name]
        if sprite.java_class in TIMED_CLASSES:
            found[name] = f"{sprite.java_class} keeps an age"
        if sprite.java_class == "SpawnPoint" and sprite.value("total"):
            found[name] = "a SpawnPoint with total keeps a count"
        elif sprite.java_class == "SpawnPoint" and name in made:  # Java times it from its first update
            found[name] = "a SpawnPoint made during play keeps its start tick"
    for effect in game.effects:
        spends = effect.name == "spawnIfHasMore" and effect.value("spend")
        if effect.name in FIRST_STATE_EFFECTS or spends:
            for name in leaves(game, effect.first):
                found.setdefault(name, f"{effect.name} (line {effect.line}) changes what it holds")
        subtracts = effect.name == "killIfOtherHasMore" and effect.value("subtract")
        if effect.name in SECOND_STATE_EFFECTS or subtracts:
            for second in effect.seconds:
                for name in leaves(game, second):
                    found.setdefault(name, f"{effect.name} (line {effect.line}) changes what it holds")
    return found


def own_axes(game: GameDescription, name: str, turned: frozenset[str]) -> tuple[str, ...]:
    """The axes along which a type's own update may move it: none for a still class, one for a
    Missile whose orientation is fixed along it (a lane), both otherwise."""
    sprite = game.types[name]
    if sprite.java_class in STILL_CLASSES:
        return ()
    orientation = sprite.value("orientation")
    facing = orientation.name if isinstance(orientation, Const) else ""
    if sprite.java_class == "Missile" and name not in turned:
        if facing in ("DLEFT", "DRIGHT"):
            return ("x",)
        if facing in ("DUP", "DDOWN"):
            return ("y",)
    return AXES


def turned_types(game: GameDescription) -> frozenset[str]:
    """Types whose orientation may differ from their type's: turned by a rule, or made with an
    orientation other than their own (Java's SpawnPoint ``spawnorientation``, a transform's
    ``forceOrientation``, or a creation into a type with no orientation of its own)."""
    found = {
        name for name, rules in movers(game).items() if any(e.name not in KEEP_ORIENTATION for e, _ in rules)
    }
    for effect in game.effects:
        if effect.name in CREATING_EFFECTS and effect.value("forceOrientation"):
            found.update(created_types(game, effect))
    for name, ways in creations(game).items():
        spawner = [game.types[way.source].value("spawnorientation") for way in ways]
        if any(isinstance(o, Const) and o.name != "DNONE" for o in spawner):
            found.add(name)
    return frozenset(found)


def unaligned_axes(game: GameDescription, types: tuple[str, ...]) -> dict[str, dict[str, str]]:
    """Per type, the axes (``x``, ``y``) on which its sprites may leave whole cells, each with
    the first reason found: a fixed point over steps, creations and moves."""
    made, moved, turned = creations(game), movers(game), turned_types(game)
    # The axes a sprite's last move may lie on (what it pushes moves along them): its own, or
    # both where a rule moves it too.
    carried = {
        name
        for name, rules in moved.items()
        if any(e.name in PUSHING_EFFECTS | FOLLOWING_EFFECTS for e, _ in rules)
    }
    own = {name: own_axes(game, name, turned) for name in types}
    axes = {name: AXES if name in carried else own[name] for name in types}
    off: dict[str, dict[str, str]] = {name: {} for name in types}
    for name in types:
        step = speed_px(game.types[name])
        if step % CELL:
            off[name].update({axis: f"a move is {step} px, not whole cells" for axis in own[name]})
    changed = True
    while changed:
        changed = False
        for name in types:
            found: dict[str, str] = {}
            for way in made.get(name, ()):
                for axis in off.get(way.source, {}):
                    found.setdefault(axis, f"made by {way.how} where {way.source} is")
            for effect, target in moved.get(name, ()):
                for axis, why in _moved_off_cells(game, effect, target, off, axes, own[name]).items():
                    found.setdefault(axis, why)
            for axis, why in found.items():
                if axis not in off[name]:
                    off[name][axis] = why
                    changed = True
    return off


def _moved_off_cells(
    game: GameDescription,
    effect: Effect,
    target: str,
    off: Mapping[str, Mapping[str, str]],
    axes: Mapping[str, tuple[str, ...]],
    own: tuple[str, ...],
) -> dict[str, str]:
    """The axes on which a move by ``effect`` (second ``target``) may leave a sprite that moves
    itself along ``own`` off the cells, with the reason; ``axes`` are those each type's last
    move may lie on."""
    if effect.name in PUSHING_EFFECTS:  # along the second's last move, by the second's speed
        odd = [leaf for leaf in leaves(game, target) if push_px(game.types[leaf]) % CELL]
        pushed = {axis for leaf in odd for axis in axes.get(leaf, AXES)} or set(AXES) if odd else set()
        step = push_px(game.types[odd[0]]) if odd else 0
        return {
            axis: f"moved {step} px by {effect.name} (line {effect.line})" for axis in AXES if axis in pushed
        }
    if effect.name in FOLLOWING_EFFECTS:
        return {
            axis: f"moved by {effect.name} (line {effect.line}) to {target}"
            for leaf in leaves(game, target)
            for axis in off.get(leaf, {})
        }
    offset = effect.value("offset") if effect.name == "wrapAround" else 0
    if isinstance(offset, int | float) and int(offset * CELL) % CELL:
        why = f"wrapped {int(offset * CELL)} px from the edge (line {effect.line})"
        return {axis: why for axis in own or AXES}
    return {}


def capacities(
    game: GameDescription, types: tuple[str, ...], representation: Mapping[str, str]
) -> dict[str, Capacity]:
    """Each table's slots as a formula over a level; records hold one, grids need none.

    A formula bounds how many sprites of the type an episode can ever make (so it bounds those
    alive at once): the level's own, plus for each bounded creation that many times what its
    source can ever be (a record included: an avatar made again may transform again)."""
    made = creations(game)
    result: dict[str, Capacity] = {}

    def of(name: str, visiting: tuple[str, ...]) -> Capacity:
        if name in result:
            return result[name]
        ways = made.get(name, [])
        if not ways:
            return Capacity((name,), 0, 0, "the level's own")
        level_types, constant = [name], 0
        for way in ways:
            if way.bounded_by is None or way.source in visiting or way.source == name:
                return Capacity((name,), 0, HEADROOM_PER_CELL, f"{way.how} (line {way.line}) has no bound")
            source = of(way.source, (*visiting, name))
            if source.per_cell:
                return Capacity((name,), 0, HEADROOM_PER_CELL, f"{way.source} has no bound")
            level_types += list(source.level_types) * way.bounded_by
            constant += source.constant * way.bounded_by
        why = "the level's own + what " + ", ".join(dict.fromkeys(w.source for w in ways)) + " can become"
        return Capacity(tuple(level_types), constant, 0, why)

    for name in types:
        if representation[name] == TABLE:
            result[name] = of(name, ())
    return result
