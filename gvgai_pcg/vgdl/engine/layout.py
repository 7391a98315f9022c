"""Where each type of a plan lives in the batched state, and the state a batch of levels starts in.

The plan says per type ``grid``, ``record`` or ``table`` (``gvgai_pcg.vgdl.layout``); here they
become state entries:

- a grid type is a ``[B, H, W]`` uint8 count grid under its own name;
- a record type is a ``[B]`` TensorDict under its own name (``x, y, lastx, lasty, ori, alive``,
  and ``age`` for a Flicker);
- table types are grouped: the table types of one class whose nearest parent is the same type
  share one ``[B, K]`` table (under the parent's name, or the leaf's own name for a type with no
  parent) with a ``kind`` column, the kind codes being the leaves in the parent's ``iSubTypes``
  order. Slots follow ``(kind, row-major cell)`` (``base.char_entities``): Java's processing
  order of a rule that names the parent, so a same-group ``stepBack`` resolves in slot order.

**Draw keys.** A random draw is ``rng`` of ``(seed, tick, slot, stream)``: ``slot`` is the
sprite's slot in its group's table, ``stream`` is ``1 + `` the rank of its group among the
groups that draw (in drawing order of each group's first kind). Every draw of one sprite in one
tick therefore has its own key, whatever the batch, and Zelda's three monster types (one group,
the only one that draws) draw exactly what the hand-written engine draws with its one monster
table and stream 1. Where a hand-written engine numbers its sprites in another order of the kinds
(Boulderdash: butterflies before crabs, its update order, where the slots put crabs first), a
game names that order (``draw_order``) and each sprite draws with its rank in it (``draw``), the
slots keeping Java's processing order.

**Resources.** A record that a ``collectResource`` can give to holds one count per resource
type, ``resource_<type>`` (Java's resources map; the snapshot lists the counts above zero).

The still spawners (grid ``SpawnPoint`` types) draw as one more such group,
ranked by their first type in drawing order, keyed by their cell (``SPAWNER_ROW``): Frogs' two
forests draw what the hand-written Frogs draws.

**Missiles** (tables) carry ``ori`` (their direction code, the kind's default), ``fresh`` (the
first update, which does not move, is still to come) and ``born`` (Java's list order: a level
sprite's slot, then ``(tick + 1) * BORN_TICK + rank`` for one created during play), since slots
are reused and so are not list order.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import torch
from tensordict import TensorDict

from gvgai_pcg.games.base import char_codes, char_entities, common_state, on_device
from gvgai_pcg.games.geometry import CELL, DOWN, LEFT, NONE, RIGHT, UP
from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl.engine.columns import fresh_columns, oriented_table
from gvgai_pcg.vgdl.engine.off_grid import off_key
from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.layout import GRID, RECORD, TABLE, is_avatar
from gvgai_pcg.vgdl.model import GameDescription
from gvgai_pcg.vgdl.plan import Plan

# Java's direction constants as the package's direction codes.
DIRECTION_CODES = {"DLEFT": LEFT, "DRIGHT": RIGHT, "DDOWN": DOWN, "DUP": UP, "DNONE": NONE, "DNIL": NONE}
# Classes whose sprites draw a random number at each update, held in a table; and those held
# in a grid, whose draws are keyed by their cell (``SPAWNER_ROW``).
DRAWING_CLASSES = frozenset({"RandomNPC"})
DRAWING_GRID_CLASSES = frozenset({"SpawnPoint"})
# Effects that make sprites of their ``stype`` (where their first is, or instead of it).
CREATING_RULES = frozenset({"transformTo", "spawn", "spawnIfHasMore"})
# A still spawner's draw slot: ``y * SPAWNER_ROW + x`` in px, whatever the level's width.
SPAWNER_ROW = 1 << 16
FLICKERS = frozenset({"Flicker", "OrientedFlicker"})
# A created sprite's ``born``: ``(tick + 1) * BORN_TICK + its rank among the tick's creations``.
BORN_TICK = 1 << 20


@dataclass(frozen=True)
class TableGroup:
    key: str  # its state entry
    kinds: tuple[str, ...]  # leaf types, kind code = index
    java_class: str
    stream: int  # the rng stream of its draws; 0 for a group that draws nothing


@dataclass(frozen=True)
class Place:
    """Where one type's sprites are: its representation, state entry and kind code (tables)."""

    representation: str
    key: str
    kind: int = 0


@dataclass(frozen=True)
class Layout:
    plan: Plan
    types: tuple[str, ...]  # the types whose sprites can exist, drawing order
    grids: tuple[str, ...]  # drawing order
    records: tuple[str, ...]
    tables: tuple[TableGroup, ...]
    places: Mapping[str, Place]
    avatars: tuple[str, ...]  # record types of an avatar class
    orientation: Mapping[str, int]  # each type's default direction code
    spawner_stream: int = 0  # the rng stream of the still spawners' draws; 0 if none
    draw_order: tuple[str, ...] = ()  # kinds in the order they take draw keys (``draw``)
    # grid types a table transforms into -> that table: their sprites off the array (``off_grid``)
    spills: Mapping[str, str] = field(default_factory=dict)

    def group(self, key: str) -> TableGroup:
        return next(group for group in self.tables if group.key == key)

    def representation(self, key: str) -> str:
        """The representation of state entry ``key``."""
        return GRID if key in self.grids else RECORD if key in self.records else TABLE


def make_layout(game: GameDescription, plan: Plan, draw_order: tuple[str, ...] = ()) -> Layout:
    """The state layout of ``plan`` (``game`` gives the parents that group the tables); a drawing
    group's kinds named in ``draw_order`` take draw keys in that order (see the docstring)."""
    types = existing_types(plan)
    grids = tuple(name for name in types if plan.types[name].representation == GRID)
    records = tuple(name for name in types if plan.types[name].representation == RECORD)
    places: dict[str, Place] = {name: Place(GRID, name) for name in grids}
    places.update({name: Place(RECORD, name) for name in records})
    grouped: dict[tuple[str, str], list[str]] = {}
    for name in types:
        sprite = plan.types[name]
        if sprite.representation == TABLE:
            parent = game.types[name].parent or name
            grouped.setdefault((parent, sprite.java_class), []).append(name)
    classes_per_parent: dict[str, int] = {}
    for parent, _ in grouped:
        classes_per_parent[parent] = classes_per_parent.get(parent, 0) + 1
    tables, stream, spawner_stream = [], 0, 0
    first_spawner = next(
        (name for name in grids if plan.types[name].java_class in DRAWING_GRID_CLASSES), None
    )
    for (parent, java_class), members in grouped.items():
        order = game.types[parent].subtypes if parent in game.types else (parent,)
        kinds = tuple(sorted(members, key=order.index))
        key = parent if classes_per_parent[parent] == 1 else f"{parent}_{java_class}"
        if (
            first_spawner is not None
            and not spawner_stream
            and types.index(first_spawner) < types.index(members[0])
        ):
            stream += 1
            spawner_stream = stream
        draws = java_class in DRAWING_CLASSES or draws_in_rules(plan, kinds)
        stream += draws
        tables.append(TableGroup(key, kinds, java_class, stream if draws else 0))
        places.update({name: Place(TABLE, key, code) for code, name in enumerate(kinds)})
    drawing = {name for group in tables if group.stream for name in group.kinds}
    stray = [name for name in draw_order if name not in drawing]
    if stray:
        raise ValueError(f"draw_order names {stray[0]!r}, which is no kind of a table that draws")
    avatars = tuple(name for name in records if is_avatar(game.types[name]))
    orientation = {
        name: DIRECTION_CODES[getattr(sprite.values.get("orientation"), "name", "DNONE")]
        for name, sprite in plan.types.items()
    }
    spills: dict[str, str] = {}
    for rule in plan.pairs:
        made = rule.values.get("stype")
        if rule.name != "transformTo" or made not in grids:
            continue
        held = (name for name in rule.firsts if name in places and places[name].representation == TABLE)
        for source in {places[name].key for name in held}:
            if spills.setdefault(str(made), source) != source:
                raise VGDLError(
                    plan.path, rule.line, f"transformTo into {made} from two tables is not implemented"
                )
    if first_spawner is not None and not spawner_stream:
        spawner_stream = stream + 1
    return Layout(
        plan,
        types,
        grids,
        records,
        tuple(tables),
        places,
        avatars,
        orientation,
        spawner_stream,
        draw_order=draw_order,
        spills=spills,
    )


def draws_in_rules(plan: Plan, kinds: tuple[str, ...]) -> bool:
    """Whether sprites of ``kinds`` draw as the first of a rule: a ``spawn`` with ``prob`` below 1
    (one of 1 always fires, so it needs no draw)."""
    return any(
        rule.name == "spawn" and float(rule.values["prob"]) < 1 and set(rule.firsts) & set(kinds)
        for rule in plan.pairs
    )


def existing_types(plan: Plan) -> tuple[str, ...]:
    """The types whose sprites can exist: those a level character places, and, as a fixed point,
    the ``stype`` of a ShootAvatar, a SpawnPoint or a creating rule whose source can exist. The
    rest (Zelda's ``avatar``, a parent type with a class that nothing places) get no state and no work."""
    found = {name for types in plan.level_mapping.values() for name in types if name in plan.types}
    while True:
        made = {
            str(plan.types[name].values["stype"])
            for name in found
            if plan.types[name].java_class in ("ShootAvatar", "SpawnPoint")
        }
        made |= {
            str(rule.values["stype"])
            for rule in plan.pairs
            if rule.name in CREATING_RULES and found & set(rule.firsts)
        }
        if made <= found:
            return tuple(name for name in plan.types if name in found)
        found |= made


def compile_state(
    layout: Layout, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device
) -> TensorDict:
    """The state of ``levels`` before the reset tick: every sprite a level character places
    (through the description's LevelMapping), each type where ``layout`` puts it."""
    mapping = layout.plan.level_mapping
    codes = char_codes(levels)
    batch, height, width = codes.shape
    _check_characters(codes, mapping, levels)
    state: dict[str, object] = dict(common_state(levels, seeds, device))
    spawners = np.zeros(256, dtype=np.int64)
    for name in layout.grids:
        per_char = np.zeros(256, dtype=np.uint8)
        for char, types in mapping.items():
            per_char[ord(char)] = types.count(name)
            if layout.plan.types[name].java_class in DRAWING_GRID_CLASSES:
                spawners[ord(char)] += types.count(name)
        state[name] = torch.from_numpy(per_char[codes]).to(device)
    if (spawners > 1).any():  # their draws are keyed by cell: two in one cell would draw alike
        char = chr(int(np.flatnonzero(spawners > 1)[0]))
        raise ValueError(f"level character {char!r} places two spawners in one cell; the engine holds one")
    for name in layout.records:
        state[name] = _record(layout, name, codes, mapping, levels, device)
    for group in layout.tables:
        state[group.key] = _table(layout, group, levels, mapping, device)
    for name, source in layout.spills.items():
        table = state[source]
        zeros = torch.zeros(table.batch_size, dtype=torch.int64, device=device)
        values = {"x": zeros, "y": zeros.clone(), "alive": zeros.bool()}
        state[off_key(name)] = TensorDict(values, batch_size=table.batch_size, device=device)
    return on_device(device, state, [batch])


def table_slots(largest: int) -> int:
    """A table's slots for a batch whose largest level places ``largest`` sprites in it: at least
    two, in powers of two (as a running env grows its tables), so that batches of nearby sizes
    share one compiled tick (a same-table stepBack unrolls over the slots)."""
    return max(2, 1 << max(0, largest - 1).bit_length())


def _check_characters(
    codes: np.ndarray, mapping: Mapping[str, tuple[str, ...]], levels: Sequence[Level]
) -> None:
    known = np.zeros(256, dtype=bool)
    known[[ord(char) for char in mapping if ord(char) < 256]] = True
    known[ord(" ")] = True  # padding beyond a smaller level's screen
    unknown = ~known[codes]
    if unknown.any():
        env, row, column = (int(i) for i in np.argwhere(unknown)[0])
        char = chr(codes[env, row, column])
        name = levels[env].name or f"level {env}"
        raise ValueError(f"{name}: row {row + 1}: character {char!r} is not in the game's LevelMapping")


def _record(
    layout: Layout,
    name: str,
    codes: np.ndarray,
    mapping: Mapping[str, tuple[str, ...]],
    levels: Sequence[Level],
    device: torch.device,
) -> TensorDict:
    batch, _, width = codes.shape
    places = np.zeros(256, dtype=np.int64)
    for char, types in mapping.items():
        places[ord(char)] = types.count(name)
    count = places[codes].reshape(batch, -1)
    many = np.flatnonzero(count.sum(1) > 1)
    if many.size:
        level = levels[int(many[0])]
        raise ValueError(f"{level.name or 'a level'} places more than one {name!r}, a type that holds one")
    present = count.sum(1) > 0
    cell = count.argmax(1)
    x = torch.from_numpy(np.where(present, CELL * (cell % width), 0))
    y = torch.from_numpy(np.where(present, CELL * (cell // width), 0))
    values = {
        "x": x,
        "y": y,
        "lastx": x.clone(),
        "lasty": y.clone(),
        "ori": torch.full((batch,), layout.orientation[name], dtype=torch.int64),
        "alive": torch.from_numpy(present),
    }
    for column, value in fresh_columns(layout.plan, (name,)).items():
        values[column] = torch.full((batch,), value)
    return on_device(device, values, [batch])


def _table(
    layout: Layout,
    group: TableGroup,
    levels: Sequence[Level],
    mapping: Mapping[str, tuple[str, ...]],
    device: torch.device,
) -> TensorDict:
    kinds: dict[str, int] = {}
    for char, types in mapping.items():
        placed = [name for name in types if name in group.kinds]
        if len(placed) > 1:
            raise ValueError(
                f"level character {char!r} places {len(placed)} sprites of the table {group.key!r}; "
                "the engine holds one per character"
            )
        if placed:
            kinds[char] = group.kinds.index(placed[0])
    placing = np.zeros(256, dtype=np.int64)
    placing[[ord(char) for char in kinds]] = 1
    largest = int(placing[char_codes(levels)].reshape(len(levels), -1).sum(1).max(initial=0))
    if any(layout.plan.types[name].created_by for name in group.kinds):
        largest = max(largest, max(_created_capacity(layout, group, level) for level in levels))
    table = char_entities(levels, kinds, device, capacity=table_slots(largest))
    batch, slots = table.batch_size
    table.update({"lastx": table.get("x").clone(), "lasty": table.get("y").clone()})
    if oriented_table(layout.plan, group.kinds):
        ori = torch.tensor([layout.orientation[name] for name in group.kinds], device=device)
        table.set("ori", ori[table.get("kind")])
    for column, value in fresh_columns(layout.plan, group.kinds).items():
        table.set(column, torch.full((batch, slots), value, device=device))
    if "fresh" in table.keys():  # the born column: a level sprite's list order is its slot
        table.set("born", torch.arange(slots, device=device).expand(batch, slots).clone())
    if group.stream:
        table.set("draw", _draw_ranks(layout, group, table))
    return table


def _draw_ranks(layout: Layout, group: TableGroup, table: TensorDict) -> torch.Tensor:
    """Each slot's draw key: its rank by (kind in ``draw_order``, slot), the free slots last in
    slot order; without a ``draw_order`` for the group, the slot itself."""
    named = [name for name in layout.draw_order if name in group.kinds]
    order = named + [name for name in group.kinds if name not in named]
    rank = torch.tensor([order.index(name) for name in group.kinds], device=table.device)
    kind, alive = table.get("kind"), table.get("alive")
    slots = kind.shape[1]
    slot = torch.arange(slots, device=kind.device).expand_as(kind)
    key = torch.where(alive, rank[kind] * slots + slot, len(order) * slots + slot)
    return key.argsort(dim=1).argsort(dim=1)


def _created_capacity(layout: Layout, group: TableGroup, level: Level) -> int:
    """Slots the plan's capacity formulas (``gvgai_pcg.vgdl.layout.Capacity``) give ``group`` for
    ``level``: the table is sized once, and a creation that finds it full is an error."""
    slots = layout.plan.table_slots(level.rows)
    return sum(slots.get(name, 0) for name in group.kinds)
