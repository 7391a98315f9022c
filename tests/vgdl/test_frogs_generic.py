"""The generic step runs Frogs from a VGDL description exactly as the hand-written engine does.

The description is the package's own (``gvgai_pcg/vgdl/descriptions/frogs.txt``, written from
RULES.md §6), whose parse must equal Java's parse of GVGAI's frogs. On random actions over human and
generated levels (batched with different sizes, and alone; eager and through the engine's compiled
tick) both engines give the same golden record, score and outcome at every tick, the logs' spawns
included (the same draws); the Frogs golden traces of the Java engine replay through it; and GVGAI's
own frogs.txt gives the same where the corpus is present (``GVGAI_VGDL_DIR``).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
import torch

from gvgai_pcg.engine.compiled import CompiledTick, engine_tick
from gvgai_pcg.games import get_game
from gvgai_pcg.games.registry import generate_level
from gvgai_pcg.games.render import render_tiles
from gvgai_pcg.levels import Level, human_levels
from gvgai_pcg.vgdl import parse_file
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.registry import registered_game
from tests.games.golden_replay import assert_replays, golden_files

HERE = Path(__file__).parent
OWN_FROGS = registered_game("frogs").description
ROOT = HERE.parents[1]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"
# Random play with NIL half the time: a frog on a log stays on it long enough to be carried.
ACTION_WEIGHTS = torch.tensor([4.0, 1.0, 1.0, 1.0, 1.0])

# Small levels, some without a border (sprites leave their own screen), to batch with full-size ones.
SMALL_LEVELS = (
    ("wgw", "==1", "+A+"),
    ("g+++", "0=34", "-..x", "+A+l"),
    ("+g", "B2"),
    ("....g", "_l.-x", "==0=1", "B=0=3", "+++++"),
)


def own_frogs() -> VGDLGame:
    return VGDLGame.from_file(OWN_FROGS, name="vgdl:frogs")


def generated(count_per_d: int) -> list[Level]:
    return [generate_level("frogs", d / 4, seed) for d in range(5) for seed in range(count_per_d)]


def small_levels() -> list[Level]:
    return [Level("frogs", rows, name=f"small{index}") for index, rows in enumerate(SMALL_LEVELS)]


def assert_same_play(game: VGDLGame, levels: list[Level], ticks: int, compiled: bool, seed: int = 0) -> dict:
    """Tick ``game`` and the hand-written Frogs side by side on random actions; every env's golden
    record must agree at every tick. ``compiled`` ticks ``game`` through the engine's compiled tick.
    Returns what happened, for the callers' coverage checks."""
    frogs = get_game("frogs")
    seeds = torch.arange(len(levels)) * 7919 + seed
    mine, theirs = game.compile(levels, seeds, "cpu"), frogs.compile(levels, seeds, "cpu")
    tick_mine = engine_tick(game) if compiled else game.tick
    generator = torch.Generator().manual_seed(seed)
    seen = {"carried": 0, "spawned": 0, "win": 0, "lose": 0}
    logs = torch.zeros(len(levels), dtype=torch.int64)
    for step in range(ticks):
        action = torch.multinomial(ACTION_WEIGHTS, len(levels), replacement=True, generator=generator)
        action = action if step else torch.zeros_like(action)  # tick 0 is the reset tick: NIL
        tick_mine(mine, action)
        frogs.tick(theirs, action)
        for key in ("score", "won", "lost"):
            assert torch.equal(mine.get(key), theirs.get(key)), f"{key} differs at tick {step}"
        for index in range(len(levels)):
            expected, actual = frogs.snapshot(theirs, index), game.snapshot(mine, index)
            assert actual == expected, f"{levels[index].name} at tick {step}:\n{expected}\n{actual}"
        avatar = mine.get("avatar")
        seen["carried"] += int((avatar.get("alive") & (avatar.get("x") % 10 != 0)).sum())
        count = mine.get(("log", "alive")).sum(-1)
        seen["spawned"] += int((count > logs).sum()) if step else 0
        logs = count
    fresh = game.compile(levels, seeds, "cpu")  # the tick writes its fields back unchecked
    for key in fresh.keys(True, True):
        assert (mine.get(key).dtype, mine.get(key).shape) == (fresh.get(key).dtype, fresh.get(key).shape), key
    seen["win"] = int(mine.get("won").sum())
    seen["lose"] = int(mine.get("lost").sum())
    # the observation too: the same tiles, channel for channel (the orders of the types differ)
    channels = [game.tile_types.index(name) for name in frogs.tile_types]
    assert torch.equal(render_tiles(game, mine)[:, channels], render_tiles(frogs, theirs))
    return seen


@pytest.mark.skipif(not STRUCTURE.is_file(), reason=f"Java's parse ({STRUCTURE}) is not here")
def test_own_description_parses_as_java_parses_gvgai_frogs():
    rows = [json.loads(line) for line in STRUCTURE.read_text().splitlines() if line.strip()]
    java = next(row for row in rows if Path(row["file"]).name == "frogs.txt")
    game = parse_file(OWN_FROGS)
    assert list(game.sprite_order) == java["sprite_order"]
    assert [[pair.first, pair.second, len(pair.effects)] for pair in game.pairs] == java["pairs"]
    assert list(game.eos) == java["eos"]
    assert {name: list(sprite.subtypes) for name, sprite in game.types.items()} == java["subtypes"]


def test_generic_frogs_equals_the_hand_written_batched_eager():
    levels = human_levels("frogs") + generated(1) + small_levels()
    assert len({(level.height, level.width) for level in levels}) > 1  # sizes differ in the batch
    seen = assert_same_play(own_frogs(), levels, ticks=100, compiled=False)
    assert seen["carried"] > 0 and seen["spawned"] > 0 and seen["lose"] > 0


@pytest.mark.slow  # 40 s of compiling; Zelda's compiled play stays in make test
def test_generic_frogs_equals_the_hand_written_batched_compiled():
    levels = human_levels("frogs")[:2] + generated(1)[::2] + small_levels()
    seen = assert_same_play(own_frogs(), levels, ticks=40, compiled=True, seed=1)
    assert seen["spawned"] > 0
    tick = engine_tick(own_frogs())
    assert isinstance(tick, CompiledTick) and tick.failed is None  # it ran compiled


@pytest.mark.parametrize("index", [4, 7])  # lvl4 (the frog starts on a log), a small one without a border
def test_generic_frogs_alone(index):
    level = (human_levels("frogs") + small_levels())[index]
    assert_same_play(own_frogs(), [level], ticks=100, compiled=False, seed=index)


@pytest.mark.parametrize("batched", [False, True], ids=["alone", "batched"])
@pytest.mark.parametrize("path", golden_files("frogs"), ids=lambda p: p.stem)
def test_generic_frogs_replays_gvgai_traces(path, batched):
    assert_replays(path, batched, own_frogs())


@pytest.mark.skipif(
    not (GAMES / "frogs.txt").is_file(), reason=f"GVGAI's frogs.txt is not in {GAMES}; set GVGAI_VGDL_DIR"
)
def test_gvgai_frogs_description_equals_the_hand_written():
    game = VGDLGame.from_file(GAMES / "frogs.txt")
    levels = human_levels("frogs") + generated(1) + small_levels()
    # eager only: its class is another than the own description's, and compiling it would cost
    # `make test` another compilation for what the own description's compiled cases already hold
    assert_same_play(game, levels, ticks=100, compiled=False, seed=3)


@pytest.mark.slow
@pytest.mark.parametrize("compiled", [False, True], ids=["eager", "compiled"])
def test_generic_frogs_long_random_play(compiled):
    levels = human_levels("frogs") + generated(4) + small_levels()
    for seed in range(3):
        seen = assert_same_play(own_frogs(), levels, ticks=400, compiled=compiled, seed=20 + seed)
        assert seen["win"] > 0 and seen["carried"] > 0
