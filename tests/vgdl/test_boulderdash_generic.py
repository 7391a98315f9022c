"""The generic step runs Boulderdash from a VGDL description exactly as the hand-written engine does.

The description is the package's own (``gvgai_pcg/vgdl/descriptions/boulderdash.txt``, written from
RULES.md §7), whose parse must equal Java's parse of GVGAI's boulderdash. On random actions over
human, generated and small unbordered levels (batched with different sizes, and alone; eager and
through the engine's compiled tick) both engines give the same golden record, score and outcome at
every tick, monsters' random walks included: the hand-written engine keys its monsters' draws
butterflies first, which the generic step is told with ``draw_order``. The Boulderdash golden traces
of the Java engine replay through it; GVGAI's own boulderdash.txt gives the same where the corpus is
present (``GVGAI_VGDL_DIR``).
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
from gvgai_pcg.levels import Level, human_levels
from gvgai_pcg.vgdl import parse_file
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.engine.off_grid import off_key
from gvgai_pcg.vgdl.registry import registered_game
from tests.games.golden_replay import assert_replays, golden_files

HERE = Path(__file__).parent
OWN_BOULDERDASH = registered_game("boulderdash").description
ROOT = HERE.parents[1]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"
# The hand-written engine's monster slots: butterflies, then crabs (its update order).
DRAW_ORDER = registered_game("boulderdash").draw_order
# Small levels, most without a border (sprites leave their screen), to batch with full-size ones.
SMALL_LEVELS = (
    ("A-b", "-c-", "o.x"),
    ("bc-o", "-A-.", "x-e."),
    ("wwwww", "wAxbw", "w-o.w", "wcx-w", "wwwww"),
    ("o-o", "A-c", "b-x", "--e"),
)


def own_boulderdash() -> VGDLGame:
    return VGDLGame.from_file(OWN_BOULDERDASH, name="vgdl:boulderdash", draw_order=DRAW_ORDER)


def generated(count_per_d: int) -> list[Level]:
    return [generate_level("boulderdash", d / 4, seed) for d in range(5) for seed in range(count_per_d)]


def small_levels() -> list[Level]:
    return [Level("boulderdash", rows, name=f"small{index}") for index, rows in enumerate(SMALL_LEVELS)]


def assert_same_play(game: VGDLGame, levels: list[Level], ticks: int, compiled: bool, seed: int = 0) -> dict:
    """Tick ``game`` and the hand-written Boulderdash side by side on random actions; every env's
    golden record, score and outcome must agree at every tick. Returns what happened."""
    boulderdash = get_game("boulderdash")
    seeds = torch.arange(len(levels)) * 7919 + seed
    mine, theirs = game.compile(levels, seeds, "cpu"), boulderdash.compile(levels, seeds, "cpu")
    tick_mine = engine_tick(game) if compiled else game.tick
    generator = torch.Generator().manual_seed(seed)
    for step in range(ticks):
        action = torch.randint(0, game.num_actions, (len(levels),), generator=generator)
        tick_mine(mine, action)
        boulderdash.tick(theirs, action)
        for key in ("score", "won", "lost"):
            assert torch.equal(mine.get(key), theirs.get(key)), f"{key} differs at tick {step}"
        for index in range(len(levels)):
            expected, actual = boulderdash.snapshot(theirs, index), game.snapshot(mine, index)
            assert actual == expected, f"{levels[index].name} at tick {step}:\n{expected}\n{actual}"
    return {
        "win": int(mine.get("won").sum()),
        "lose": int(mine.get("lost").sum()),
        "diamonds": int(mine.get(("avatar", "resource_diamond")).sum()),
        "off_grid": int(mine.get((off_key("diamond"), "alive")).sum()),
    }


@pytest.mark.skipif(not STRUCTURE.is_file(), reason=f"Java's parse ({STRUCTURE}) is not here")
def test_own_description_parses_as_java_parses_gvgai_boulderdash():
    rows = [json.loads(line) for line in STRUCTURE.read_text().splitlines() if line.strip()]
    java = next(row for row in rows if Path(row["file"]).name == "boulderdash.txt")
    game = parse_file(OWN_BOULDERDASH)
    assert list(game.sprite_order) == java["sprite_order"]
    assert [[pair.first, pair.second, len(pair.effects)] for pair in game.pairs] == java["pairs"]
    assert list(game.eos) == java["eos"]
    assert {name: list(sprite.subtypes) for name, sprite in game.types.items()} == java["subtypes"]


def test_generic_boulderdash_equals_the_hand_written_batched_eager():
    levels = human_levels("boulderdash") + generated(1) + small_levels()
    assert len({(level.height, level.width) for level in levels}) > 1  # sizes differ in the batch
    seen = assert_same_play(own_boulderdash(), levels, ticks=60, compiled=False)
    assert seen["lose"] > 0 and seen["diamonds"] > 0


def test_the_draw_order_is_what_makes_the_monsters_walk_as_the_hand_written():
    levels = human_levels("boulderdash")[:2]
    crabs_first = VGDLGame.from_file(OWN_BOULDERDASH, name="vgdl:boulderdash-crabs-first")
    with pytest.raises(AssertionError):
        assert_same_play(crabs_first, levels, ticks=10, compiled=False)
    with pytest.raises(ValueError, match="draw_order names 'boulder'"):
        VGDLGame.from_file(OWN_BOULDERDASH, name="vgdl:bad", draw_order=("boulder",))


@pytest.mark.parametrize("index", [0, 1, 3])
def test_generic_boulderdash_alone_off_the_grid(index):
    # alone, an unbordered level's array is its screen: monsters walk off it, and a butterfly a crab
    # meets out there leaves its diamond off the grid (seeds where that happens)
    level = small_levels()[index]
    seen = assert_same_play(own_boulderdash(), [level] * 8, ticks=60, compiled=False, seed=index + 1)
    assert seen["lose"] > 0


def test_a_butterfly_turned_off_the_grid_leaves_its_diamond_there():
    levels = [small_levels()[1]] * 8
    total = sum(
        assert_same_play(own_boulderdash(), levels, ticks=40, compiled=False, seed=seed)["off_grid"]
        for seed in range(3)
    )
    assert total > 0


@pytest.mark.slow  # a minute of compiling (the in-order stepBack of a 64-slot boulder table unrolls)
def test_generic_boulderdash_equals_the_hand_written_compiled():
    levels = generated(1)[:2] + small_levels()
    assert_same_play(own_boulderdash(), levels, ticks=40, compiled=True, seed=1)
    tick = engine_tick(own_boulderdash())
    assert isinstance(tick, CompiledTick) and tick.failed is None  # it ran compiled


@pytest.mark.parametrize("path", golden_files("boulderdash"), ids=lambda p: p.stem)
def test_generic_boulderdash_replays_gvgai_traces(path):
    assert_replays(path, True, own_boulderdash())


@pytest.mark.skipif(
    not (GAMES / "boulderdash.txt").is_file(),
    reason=f"GVGAI's boulderdash.txt is not in {GAMES}; set GVGAI_VGDL_DIR",
)
def test_gvgai_boulderdash_description_equals_the_hand_written():
    game = VGDLGame.from_file(GAMES / "boulderdash.txt", draw_order=DRAW_ORDER)
    levels = human_levels("boulderdash")[:2] + small_levels()
    assert_same_play(game, levels, ticks=40, compiled=False, seed=3)


@pytest.mark.parametrize("path", golden_files("boulderdash_offgrid"), ids=lambda p: p.stem)
def test_generic_boulderdash_replays_the_off_grid_traces_alone(path):
    # alone, the trace's small unbordered level is the whole array, and its tick runs compiled
    assert_replays(path, False, own_boulderdash())
