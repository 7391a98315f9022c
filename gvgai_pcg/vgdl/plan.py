"""A game's plan: everything the generic step needs, compiled once from a parsed description.

``compile_plan(description, level_rows=None)`` refuses what the engine does not implement
(``support.check_supported``: one line naming the file, the line and the feature), then
decides, as plain frozen data (no torch):

- per leaf type (``TypePlan``): its representation (count grid, record or pixel table, see
  ``layout``), whether it is always cell-aligned, its step in px, its behaviour fields with
  Java's defaults filled in, how it appears during play, and a table's capacity formula;
- per rule, in Java's order (EOS entries, then collision pairs with ``repeat`` applied, and the
  timed effects): the leaf types it reaches as first and second in ``iSubTypes`` order, the
  effect's fields with Java's defaults, its kind (``kinds``) and whether it draws randomness;
- the terminations with the leaf types each one counts;
- with ``level_rows``, each table's slots for that level (the step takes the largest of a batch).

The step reads nothing else: the description is not needed once the plan exists.
"""

from __future__ import annotations

import dataclasses
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from gvgai_pcg.vgdl.describe import BEHAVIOUR_FIELDS, SETTABLE
from gvgai_pcg.vgdl.java_classes import defaults_of, fields_of
from gvgai_pcg.vgdl.kinds import RANDOM_EFFECTS, leaves, rule_kind
from gvgai_pcg.vgdl.layout import (
    CELL,
    GRID,
    RECORD,
    TABLE,
    Capacity,
    Creation,
    capacities,
    creations,
    is_avatar,
    movers,
    speed_px,
    stateful,
    unaligned_axes,
)
from gvgai_pcg.vgdl.model import Effect, GameDescription, SpriteType, Termination
from gvgai_pcg.vgdl.support import STILL_CLASSES, check_supported

# Effect fields that are Java's bookkeeping, not behaviour.
ENGINE_FIELDS = frozenset({"hashCode", "enabled", "inBatch", "is_kill_effect", "sequential"})


@dataclass(frozen=True)
class TypePlan:
    name: str
    line: int  # 0 for Java's pre-defined wall/avatar
    java_class: str
    representation: str  # "grid", "record" or "table"
    why: str
    singleton: bool  # Java refuses a second sprite (its own line says singleton=True)
    aligned: bool  # on whole cells at every tick
    aligned_x: bool  # x on whole cells (a column stays a column)
    aligned_y: bool  # y on whole cells (a lane: the row stays a row)
    why_unaligned: str  # the first reason, x before y
    step_px: int  # px a move covers; 0 for a class that never moves itself
    values: Mapping[str, object]  # behaviour fields, Java's defaults filled in
    created_by: tuple[Creation, ...]
    capacity: Capacity | None  # tables only
    # the leaf types whose sprites refuse a creation of this type: Java's singleton check over the
    # type and its ancestors whose own line says singleton=True (empty: never refused)
    singleton_guard: tuple[str, ...] = ()


@dataclass(frozen=True)
class RulePlan:
    """One effect applied to one (first, second) type pair; ``second`` is ``EOS`` or ``TIME``
    for those rules. ``effect`` is the line's index: every pair of a line shares one Java
    effect object (its once-a-tick guards, its rewritten score)."""

    effect: int
    line: int
    name: str
    java_class: str
    first: str
    second: str
    firsts: tuple[str, ...]  # leaf types, Java's iSubTypes order
    seconds: tuple[str, ...]
    kind: str
    why: str
    random: bool
    values: Mapping[str, object]


@dataclass(frozen=True)
class TerminationPlan:
    line: int
    java_class: str
    win: bool
    limit: int
    counted: tuple[tuple[str, ...], ...]  # per named type (stype, or stype1, stype2, ...), its leaves
    values: Mapping[str, object]


@dataclass(frozen=True)
class Plan:
    path: str
    cell: int
    types: Mapping[str, TypePlan]  # drawing order
    update_order: tuple[str, ...]  # avatar first, then reverse drawing order
    eos: tuple[RulePlan, ...]  # Java's EOS list, each entry's effects in line order
    pairs: tuple[RulePlan, ...]  # Java's pair order, each pair's effects with repeats
    timed: tuple[RulePlan, ...]
    terminations: tuple[TerminationPlan, ...]
    level_mapping: Mapping[str, tuple[str, ...]]
    slots: Mapping[str, int] | None  # per table, for ``level_rows``; None without a level

    def rules(self) -> tuple[RulePlan, ...]:
        return self.eos + self.pairs + self.timed

    def table_slots(self, level_rows: Sequence[str]) -> dict[str, int]:
        """Each table's slots for one level (rows of characters)."""
        counts = level_counts(self, level_rows)
        cells = sum(len(row) for row in level_rows)
        return {
            name: sprite.capacity.slots(counts, cells)
            for name, sprite in self.types.items()
            if sprite.capacity is not None
        }


def compile_plan(game: GameDescription, level_rows: Sequence[str] | None = None) -> Plan:
    """The plan of a description the engine supports; ``VGDLError`` for the first feature it
    does not, ``ValueError`` for a level that does not fit (one line each)."""
    check_supported(game)
    plan = analyse(game)
    if level_rows is None:
        return plan
    return dataclasses.replace(plan, slots=plan.table_slots(level_rows))


def analyse(game: GameDescription) -> Plan:
    """The plan's analysis for any description, supported or not (corpus figures); only
    ``compile_plan`` gives a plan the step may run."""
    types = tuple(name for name in game.sprite_order if game.types[name].java_class)
    state, moved = stateful(game), movers(game)
    made = creations(game)
    off = unaligned_axes(game, types)
    unaligned = {name: axes.get("x") or axes["y"] for name, axes in off.items() if axes}
    chosen = {name: _representation(game.types[name], state, moved, unaligned) for name in types}
    tables = capacities(game, types, {name: rep for name, (rep, _) in chosen.items()})
    plans = {
        name: TypePlan(
            name=name,
            line=game.types[name].line,
            java_class=str(game.types[name].java_class),
            representation=chosen[name][0],
            why=chosen[name][1],
            singleton=game.types[name].singleton,
            aligned=name not in unaligned,
            aligned_x="x" not in off[name],
            aligned_y="y" not in off[name],
            why_unaligned=unaligned.get(name, ""),
            step_px=speed_px(game.types[name]),
            values=_sprite_values(game.types[name]),
            created_by=tuple(made.get(name, ())),
            capacity=tables.get(name),
            singleton_guard=_singleton_guard(game, name),
        )
        for name in types
    }
    eos = tuple(
        _rule(game, game.effects[index], name, "EOS") for name in game.eos for index in game.eos_effects[name]
    )
    pairs = tuple(
        _rule(game, game.effects[index], pair.first, pair.second)
        for pair in game.pairs
        for index in pair.effects
    )
    timed = tuple(
        _rule(game, game.effects[index], game.effects[index].first, "TIME") for index in game.time_effects
    )
    return Plan(
        path=game.path,
        cell=CELL,
        types=plans,
        update_order=tuple(name for name in game.update_order if name in plans),
        eos=eos,
        pairs=pairs,
        timed=timed,
        terminations=tuple(_termination(game, termination) for termination in game.terminations),
        level_mapping=dict(game.level_mapping),
        slots=None,
    )


PADDING = " "  # the batch's padding character (gvgai_pcg.games.base.OUTSIDE)


def level_counts(plan: Plan, level_rows: Sequence[str]) -> Counter[str]:
    """Sprites of each type a level starts with; a character the mapping lacks, or a second
    sprite of a record type, is refused in one line."""
    counts: Counter[str] = Counter()
    for row_index, row in enumerate(level_rows, start=1):
        for char in row:
            if char == PADDING and PADDING not in plan.level_mapping:
                continue  # beyond a smaller level's screen in a batch: no sprite there
            if char not in plan.level_mapping:
                raise ValueError(f"level row {row_index}: character {char!r} is not in the LevelMapping")
            counts.update(plan.level_mapping[char])
    for name, count in counts.items():
        sprite = plan.types.get(name)
        if sprite is None:
            raise ValueError(f"the level places {name!r}, a type with no sprites (a parent with no class)")
        if sprite.representation == RECORD and count > 1:
            raise ValueError(
                f"the level places {count} sprites of {name!r}, which holds one (avatar or singleton)"
            )
    return counts


def _representation(
    sprite: SpriteType, state: Mapping[str, str], moved: Mapping[str, list], unaligned: Mapping[str, str]
) -> tuple[str, str]:
    if is_avatar(sprite):
        return RECORD, "the avatar"
    if sprite.singleton:
        return RECORD, "a singleton"
    if sprite.java_class not in STILL_CLASSES:
        return TABLE, f"{sprite.java_class} moves"
    if sprite.name in moved:
        how = ", ".join(dict.fromkeys(effect.name for effect, _ in moved[sprite.name]))
        return TABLE, f"moved or turned by {how}"
    if sprite.name in state:
        return TABLE, state[sprite.name]
    if sprite.name in unaligned:
        return TABLE, unaligned[sprite.name]
    return GRID, "still, stateless, on whole cells"


def _singleton_guard(game: GameDescription, name: str) -> tuple[str, ...]:
    """The leaves of every type from ``name`` up its ancestors that Java registers as a singleton
    (its own line says so): a creation of ``name`` is refused while any of them has a sprite."""
    guard: list[str] = []
    current: str | None = name
    while current is not None:
        if game.types[current].singleton:
            guard += leaves(game, current)
        current = game.types[current].parent
    return tuple(dict.fromkeys(guard))


def _sprite_values(sprite: SpriteType) -> dict[str, object]:
    defaults = defaults_of("sprite", str(sprite.java_class))
    fields, base = fields_of("sprite", str(sprite.java_class)), fields_of("sprite", "VGDLSprite")
    keep = [key for key in BEHAVIOUR_FIELDS if key in defaults]
    keep += [key for key in fields if key not in base and fields[key] in SETTABLE and key in defaults]
    values = {key: defaults[key] for key in keep}
    values.update({key: sprite.values[key] for key in sprite.values if key in fields and key in values})
    return values


def _effect_values(effect: Effect) -> dict[str, object]:
    fields = fields_of("effect", effect.java_class)
    defaults = defaults_of("effect", effect.java_class)
    values = {
        key: defaults.get(key)
        for key, kind in fields.items()
        if kind in SETTABLE and key not in ENGINE_FIELDS and key != "repeat"
    }
    values.update({key: value for key, value in effect.values.items() if key != "repeat"})
    return values


def _rule(game: GameDescription, effect: Effect, first: str, second: str) -> RulePlan:
    kind, why = rule_kind(game, effect, second)
    return RulePlan(
        effect=effect.index,
        line=effect.line,
        name=effect.name,
        java_class=effect.java_class,
        first=first,
        second=second,
        firsts=leaves(game, first),
        seconds=leaves(game, second),
        kind=kind,
        why=why,
        random=effect.name in RANDOM_EFFECTS,
        values=_effect_values(effect),
    )


def _termination(game: GameDescription, termination: Termination) -> TerminationPlan:
    named = [
        str(termination.value(key))
        for key in ("stype", "stype1", "stype2", "stype3")
        if isinstance(termination.value(key), str) and termination.value(key) in game.types
    ]
    values = {**defaults_of("termination", termination.java_class), **termination.values}
    return TerminationPlan(
        line=termination.line,
        java_class=termination.java_class,
        win=str(termination.value("win")).split(",")[0].lower() == "true",  # a String in Java
        limit=int(termination.value("limit") or 0),
        counted=tuple(leaves(game, name) for name in named),
        values=values,
    )
