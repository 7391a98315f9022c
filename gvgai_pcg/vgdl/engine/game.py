"""``VGDLGame``: a ``Game`` built from a VGDL description, the generic step.

The tick is Java's ``gameCycle`` (CORPUS.md, "Java's tick") for any description whose features
have kernels here (``checks``): ``tick += 1``; the avatar first (``avatar``); every other type in
reverse drawing order (``npcs``); the EOS rules (``eos``); the collision rules pair by pair in
Java's order, each pair's effects in line order (``effects``); cleanup of the killed sprites
(``frame``); the terminations in declaration order (``terminations``). Every loop here is over
the plan's types or rules, so it unrolls when the tick is traced: there is no loop over envs or
sprites.

Each description gets a class of its own (``VGDLGame.from_text``): the engine compiles one tick
per game class (``engine.compiled.engine_tick``).
"""

from __future__ import annotations

import hashlib
import zlib
from collections.abc import Sequence
from pathlib import Path

import torch
from tensordict import TensorDict

from gvgai_pcg.games.actions import MOVE_ACTIONS, SHOOT_ACTIONS
from gvgai_pcg.games.base import Game, GridLayer, SpriteArt, SpriteLayer, golden_record, single_sprite_layer
from gvgai_pcg.games.geometry import DIRECTION_NAMES
from gvgai_pcg.games.spec import StepFacts
from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl.engine.avatar import update_avatars
from gvgai_pcg.vgdl.engine.checks import check_engine
from gvgai_pcg.vgdl.engine.columns import held_resources
from gvgai_pcg.vgdl.engine.effects import apply_rule, make_rules
from gvgai_pcg.vgdl.engine.eos import apply_edge_rules, make_edge_rules
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import CREATING_RULES, Layout, compile_state, make_layout
from gvgai_pcg.vgdl.engine.npcs import update_npcs
from gvgai_pcg.vgdl.engine.off_grid import off_key
from gvgai_pcg.vgdl.engine.terminations import check_terminations
from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.layout import GRID, RECORD
from gvgai_pcg.vgdl.model import GameDescription
from gvgai_pcg.vgdl.parser import parse_vgdl
from gvgai_pcg.vgdl.plan import compile_plan

# Each avatar class's Gym action set.
ACTION_SETS = {"ShootAvatar": SHOOT_ACTIONS, "MovingAvatar": MOVE_ACTIONS, "OngoingAvatar": MOVE_ACTIONS}
# Effects that remove their first sprite, and those that also remove their second.
KILLS_FIRST = frozenset(
    {"killSprite", "transformTo", "collectResource", "killIfOtherHasMore", "killIfFromAbove", "killBoth"}
)
_GAMES: dict[tuple[str, str, str | None, tuple[str, ...]], VGDLGame] = {}
# The widest table whose same-table stepBack ticks compiled: compiled, ``step_back_in_order`` runs
# one round per slot (no early exit in a graph), so its cost grows as slots cubed, while eagerly it
# stops when nothing changes; the hand-written Zelda draws the line at the same width
# (``zelda.rules.COMPILED_MONSTER_SLOTS``, measured there).
COMPILED_ORDERED_SLOTS = 16
# A table something creates into this wide, in a batch this large, ticks eagerly too: compiled,
# every slot is worked, eagerly only the occupied prefix (``frame``). At 1,024 envs on one thread,
# Frogs' 512 log slots and Solarfox's 256 shot slots gave about 26,000 and 55,000 steps/s
# compiled and 44,000 and 70,000 eagerly; at 64 envs compiling still pays.
WIDE_CREATED_SLOTS, WIDE_BATCH = 256, 512


class VGDLGame(Game):
    """The generic step of one description; make one with :meth:`from_text` or :meth:`from_file`."""

    name = "vgdl"
    actions = SHOOT_ACTIONS
    tile_types: tuple[str, ...] = ()
    art: dict[str, SpriteArt] = {}
    layout: Layout
    description: GameDescription

    @classmethod
    def from_text(
        cls, text: str, path: str = "<vgdl>", name: str | None = None, draw_order: tuple[str, ...] = ()
    ) -> VGDLGame:
        """The game of a description's text; the same text, path, name and draw order give the
        same game (its compiled tick is compiled once). ``draw_order``: the kinds of a drawing
        table in the order they take draw keys (``layout``), to draw what a hand-written engine
        draws."""
        key = (text, path, name, tuple(draw_order))
        if key not in _GAMES:
            _GAMES[key] = cls.from_description(parse_vgdl(text, path), name, tuple(draw_order))
        return _GAMES[key]

    @classmethod
    def from_file(
        cls, path: str | Path, name: str | None = None, draw_order: tuple[str, ...] = ()
    ) -> VGDLGame:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except UnicodeDecodeError as error:
            raise VGDLError(str(path), 0, f"not UTF-8 text ({error.reason})") from None
        return cls.from_text(text, str(path), name, draw_order)

    @classmethod
    def from_description(
        cls, description: GameDescription, name: str | None = None, draw_order: tuple[str, ...] = ()
    ) -> VGDLGame:
        """A game of a class of its own: refuses, in one line, what has no kernel."""
        plan = compile_plan(description)
        check_engine(description, plan)
        layout = make_layout(description, plan, draw_order)
        avatar_classes = {plan.types[avatar].java_class for avatar in layout.avatars}
        if len(avatar_classes) != 1:
            raise VGDLError(
                plan.path, 0, f"the generic step needs one avatar class, not {sorted(avatar_classes)}"
            )
        title = name or f"vgdl:{Path(plan.path).stem}"
        digest = hashlib.sha1(title.encode()).hexdigest()[:8]
        attributes = {
            "name": title,
            "actions": ACTION_SETS[avatar_classes.pop()],
            "tile_types": tuple(name for name in layout.types if _drawn(layout, name)),
            "art": {name: SpriteArt(_colour(name)) for name in layout.types},
            "layout": layout,
            "description": description,
        }
        subclass = type(f"VGDLGame_{digest}", (cls,), attributes)
        return subclass()

    def __init__(self) -> None:
        self.rules = make_rules(self.layout)
        self.edge_rules = make_edge_rules(self.layout)
        self.changing = _changing_types(self.layout)
        # the tables a stepBack among their own sprites resolves in slot order
        self.ordered = tuple(
            dict.fromkeys(rule.firsts[0].key for rule in self.rules if rule.plan.kind == "F")
        )
        # the tables sprites are created into during play
        self.created = tuple(
            group.key
            for group in self.layout.tables
            if any(self.layout.plan.types[name].created_by for name in group.kinds)
        )

    @property
    def step_facts(self) -> StepFacts:
        # compiled on the CPU only: its compiled tick has not been held to the eager one on CUDA yet
        return StepFacts(compiles=True, eager_when=("crowded",), compiled_devices=("cpu",))

    def host_arguments(self, state: TensorDict) -> dict[str, object]:
        """Whether a table with an ordered stepBack is wider than ``COMPILED_ORDERED_SLOTS``, or a
        batch of at least ``WIDE_BATCH`` has a table created into of ``WIDE_CREATED_SLOTS`` (their
        shapes: no sync); such a tick runs eagerly."""
        ordered = any(state.get(key).batch_size[1] > COMPILED_ORDERED_SLOTS for key in self.ordered)
        wide = state.batch_size[0] >= WIDE_BATCH and any(
            state.get(key).batch_size[1] >= WIDE_CREATED_SLOTS for key in self.created
        )
        return {"crowded": ordered or wide}

    def compile(self, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device) -> TensorDict:
        return compile_state(self.layout, levels, seeds, torch.device(device))

    def tick(self, state: TensorDict, action: torch.Tensor, crowded: bool | None = None) -> None:
        """Java's tick (see the module docstring); ``crowded`` only chooses how the engine runs it."""
        frame = Frame(self.layout, state)
        frame.put("tick", frame.value("tick") + 1)
        update_avatars(frame, action)
        update_npcs(frame)
        apply_edge_rules(frame, self.edge_rules)
        for rule in self.rules:
            apply_rule(frame, rule)
        frame.cleanup()
        check_terminations(frame)
        frame.write()

    def layers(self, state: TensorDict) -> list:
        layout, layers = self.layout, []
        for name in layout.types:
            place = layout.places[name]
            if place.representation == GRID:
                layers.append(GridLayer(name, state.get(name) > 0))
            elif place.representation == RECORD:
                oriented = name in layout.avatars
                layers.append(single_sprite_layer(name, state.get(name), oriented=oriented))
            else:
                table = state.get(place.key)
                present = table.get("alive") & (table.get("kind") == place.kind)
                layers.append(SpriteLayer(name, table.get("x"), table.get("y"), present))
        return layers

    def snapshot(self, state: TensorDict, index: int) -> dict:
        """The golden record: the avatar, and every other sprite but the still types that no rule
        removes (walls, floors), as the golden traces list them."""
        s, layout = state[index], self.layout
        avatar = None
        for name in layout.avatars:
            record = s.get(name)
            if record.get("alive").item():
                avatar = {
                    "type": name,
                    "x": record.get("x").item(),
                    "y": record.get("y").item(),
                    "orientation": DIRECTION_NAMES[record.get("ori").item()],
                    "resources": {
                        resource: record.get(f"resource_{resource}").item()
                        for resource in held_resources(layout.plan, name)
                        if record.get(f"resource_{resource}").item()
                    },
                }
        shown = (name for name in layout.types if name not in layout.avatars)
        sprites = self.sprites(
            s, [n for n in shown if layout.places[n].representation != GRID or n in self.changing]
        )
        return golden_record(s, avatar, sprites)

    def sprites(self, s: TensorDict, names: Sequence[str]) -> list[list]:
        """``[type, x, y]`` of every sprite of the types ``names`` in one env's state ``s``
        (unbatched), one entry per sprite (a grid cell holding two gives two)."""
        layout, sprites = self.layout, []
        for name in names:
            place = layout.places[name]
            if place.representation == GRID:
                grid = s.get(name)
                for row, column in grid.nonzero().tolist():
                    sprites += [[name, 10 * column, 10 * row]] * int(grid[row, column])
                if name in layout.spills:
                    off = s.get(off_key(name))
                    for slot in off.get("alive").nonzero().flatten().tolist():
                        sprites.append([name, off.get("x")[slot].item(), off.get("y")[slot].item()])
            elif place.representation == RECORD:
                record = s.get(name)
                if record.get("alive").item():
                    sprites.append([name, record.get("x").item(), record.get("y").item()])
            else:
                table = s.get(place.key)
                present = table.get("alive") & (table.get("kind") == place.kind)
                for slot in present.nonzero().flatten().tolist():
                    sprites.append([name, table.get("x")[slot].item(), table.get("y")[slot].item()])
        return sprites

    def max_score(self, level: Level) -> int:
        raise NotImplementedError(f"{self.name}: the generic step does not derive a maximum score")


def _changing_types(layout: Layout) -> frozenset[str]:
    """Grid types some rule removes or makes, and spawners (they act: the traces list them); the
    others never change and are left out of a snapshot."""
    changing = {name for name in layout.grids if layout.plan.types[name].java_class == "SpawnPoint"}
    for rule in layout.plan.pairs:
        if rule.name in KILLS_FIRST:
            changing.update(rule.firsts)
        if rule.values.get("killSecond") or rule.name == "killBoth":
            changing.update(rule.seconds)
        if rule.name in CREATING_RULES:
            changing.add(str(rule.values["stype"]))
    return frozenset(name for name in changing & set(layout.grids))


def _drawn(layout: Layout, name: str) -> bool:
    """Whether a type gets an observation channel: any but a still type no rule names (a
    spawner acts, so it has one)."""
    if layout.places[name].representation != GRID or layout.plan.types[name].java_class == "SpawnPoint":
        return True
    return any(name in rule.firsts or name in rule.seconds for rule in layout.plan.pairs)


def _colour(name: str) -> tuple[int, int, int]:
    value = zlib.crc32(name.encode())
    return (value & 255, (value >> 8) & 255, (value >> 16) & 255)
