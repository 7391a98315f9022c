"""The generic step runs Solarfox from a VGDL description exactly as the hand-written engine does.

The description is the package's own (``gvgai_pcg/vgdl/descriptions/solarfox.txt``, written
from RULES.md §5), whose parse must equal Java's parse of GVGAI's solarfox. On random actions over human and
generated levels (batched with different sizes, and alone; eager and through the engine's
compiled tick) both engines give the same golden record, score and outcome at every tick, the
enemies' shots (random) included; the Solarfox golden traces of the Java engine replay through
it; and GVGAI's own solarfox.txt gives the same where the corpus is present (``GVGAI_VGDL_DIR``).

One difference is the hand-written engine's, and documented there: it drops a shot once it is off
screen and behind the ship's reach, where Java (and the generic step) keeps it flying forever.
Records are therefore compared on screen: a shot off screen is left out of both.
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
OWN_SOLARFOX = registered_game("solarfox").description
ROOT = HERE.parents[1]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"
SHOTS = ("upshot", "downshot")
CELL = 10

# Small levels, some without a border (the ship may leave its screen), to batch with full-size ones:
# a ship next to its last blib (a win at tick 1), powerblibs beside the ship, enemies on short lanes.
SMALL_LEVELS = (
    ("Ab",),
    ("Abp",),
    ("2....", "+Apb+", "+pp++", "....1"),
    ("wwwwww", "w+A+bw", "wp++pw", "w....w", "w1.2.w", "wwwwww"),
    ("p+", "A+", "12"),
)


def own_solarfox() -> VGDLGame:
    return VGDLGame.from_file(OWN_SOLARFOX, name="vgdl:solarfox")


def generated(count_per_d: int) -> list[Level]:
    return [generate_level("solarfox", d / 4, seed) for d in range(5) for seed in range(count_per_d)]


def small_levels() -> list[Level]:
    return [Level("solarfox", rows, name=f"small{index}") for index, rows in enumerate(SMALL_LEVELS)]


def on_screen(record: dict, level: Level) -> dict:
    """``record`` without the shots that have left ``level``'s screen (see the module docstring)."""
    height = CELL * level.height
    sprites = [s for s in record["sprites"] if s[0] not in SHOTS or -CELL < s[2] < height]
    return {**record, "sprites": sprites}


def assert_same_play(game: VGDLGame, levels: list[Level], ticks: int, compiled: bool, seed: int = 0) -> dict:
    """Tick ``game`` and the hand-written Solarfox side by side on random actions; every env's golden
    record (on screen) must agree at every tick. ``compiled`` ticks ``game`` through the engine's
    compiled tick. Returns what happened, for the callers' coverage checks."""
    solarfox = get_game("solarfox")
    seeds = torch.arange(len(levels)) * 7919 + seed
    mine, theirs = game.compile(levels, seeds, "cpu"), solarfox.compile(levels, seeds, "cpu")
    tick_mine = engine_tick(game) if compiled else game.tick
    generator = torch.Generator().manual_seed(seed)
    seen = {"shots": 0, "turnings": 0, "win": 0, "lose": 0}
    for step in range(ticks):
        action = torch.randint(0, game.num_actions, (len(levels),), generator=generator)
        tick_mine(mine, action)
        solarfox.tick(theirs, action)
        for key in ("score", "won", "lost"):
            assert torch.equal(mine.get(key), theirs.get(key)), f"{key} differs at tick {step}"
        for index, level in enumerate(levels):
            expected = on_screen(solarfox.snapshot(theirs, index), level)
            actual = on_screen(game.snapshot(mine, index), level)
            assert actual == expected, f"{level.name} at tick {step}:\n{expected}\n{actual}"
            names = [sprite[0] for sprite in actual["sprites"]]
            seen["shots"] += sum(name in SHOTS for name in names)
            seen["turnings"] += names.count("powerblibturning")
    fresh = game.compile(levels, seeds, "cpu")  # the tick writes its fields back unchecked
    for key in fresh.keys(True, True):
        assert (mine.get(key).dtype, mine.get(key).shape) == (fresh.get(key).dtype, fresh.get(key).shape), key
    seen["win"] = int(mine.get("won").sum())
    seen["lose"] = int(mine.get("lost").sum())
    # the observation too: the same tiles, channel for channel (the orders of the types differ)
    channels = [game.tile_types.index(name) for name in solarfox.tile_types]
    assert torch.equal(render_tiles(game, mine)[:, channels], render_tiles(solarfox, theirs))
    return seen


@pytest.mark.skipif(not STRUCTURE.is_file(), reason=f"Java's parse ({STRUCTURE}) is not here")
def test_own_description_parses_as_java_parses_gvgai_solarfox():
    rows = [json.loads(line) for line in STRUCTURE.read_text().splitlines() if line.strip()]
    java = next(row for row in rows if Path(row["file"]).name == "solarfox.txt")
    game = parse_file(OWN_SOLARFOX)
    assert list(game.sprite_order) == java["sprite_order"]
    assert [[pair.first, pair.second, len(pair.effects)] for pair in game.pairs] == java["pairs"]
    assert list(game.eos) == java["eos"]
    assert {name: list(sprite.subtypes) for name, sprite in game.types.items()} == java["subtypes"]


def test_generic_solarfox_equals_the_hand_written_batched_eager():
    levels = human_levels("solarfox") + generated(1) + small_levels()
    assert len({(level.height, level.width) for level in levels}) > 1  # sizes differ in the batch
    seen = assert_same_play(own_solarfox(), levels, ticks=150, compiled=False)
    assert seen["shots"] > 0 and seen["turnings"] > 0 and seen["win"] > 0 and seen["lose"] > 0


@pytest.mark.slow  # 40 s of compiling on a loaded machine: over make test's share
def test_generic_solarfox_equals_the_hand_written_batched_compiled():
    levels = human_levels("solarfox")[2:] + generated(1)[::2] + small_levels()
    seen = assert_same_play(own_solarfox(), levels, ticks=80, compiled=True, seed=1)
    assert seen["shots"] > 0 and seen["lose"] > 0
    tick = engine_tick(own_solarfox())
    assert isinstance(tick, CompiledTick) and tick.failed is None  # it ran compiled


@pytest.mark.parametrize("index", [3, 7])  # a human level (powerblibs), a small one without a border
def test_generic_solarfox_alone(index):
    level = (human_levels("solarfox") + small_levels())[index]
    assert_same_play(own_solarfox(), [level], ticks=150, compiled=False, seed=index)


@pytest.mark.parametrize(
    "batched",
    # batched, the replays run compiled (engine_tick): half a minute, the first compile most of it
    [False, pytest.param(True, marks=pytest.mark.slow)],
    ids=["alone", "batched"],
)
@pytest.mark.parametrize("path", golden_files("solarfox"), ids=lambda p: p.stem)
def test_generic_solarfox_replays_gvgai_traces(path, batched):
    assert_replays(path, batched, own_solarfox())


@pytest.mark.slow  # a batched replay: compiled, as above
@pytest.mark.skipif(
    not (GAMES / "solarfox.txt").is_file(),
    reason=f"GVGAI's solarfox.txt is not in {GAMES}; set GVGAI_VGDL_DIR",
)
def test_gvgai_solarfox_description_equals_the_hand_written():
    game = VGDLGame.from_file(GAMES / "solarfox.txt")
    levels = human_levels("solarfox") + generated(1) + small_levels()
    assert_same_play(game, levels, ticks=200, compiled=False, seed=3)
    assert_replays(golden_files("solarfox")[0], True, game)


@pytest.mark.slow  # 3 x 600 ticks over 19 levels: minutes
@pytest.mark.parametrize("compiled", [False, True], ids=["eager", "compiled"])
def test_generic_solarfox_long_random_play(compiled):
    levels = human_levels("solarfox") + generated(6) + small_levels()
    for seed in range(3):
        assert_same_play(own_solarfox(), levels, ticks=600, compiled=compiled, seed=10 + seed)
