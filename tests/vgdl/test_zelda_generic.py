"""The generic step runs Zelda from a VGDL description exactly as the hand-written engine does.

The description is the package's own (``gvgai_pcg/vgdl/descriptions/zelda.txt``, written from
RULES.md §4), whose parse must equal Java's parse of GVGAI's zelda. On random actions over human
and generated levels (batched with different sizes, and alone; eager and through the engine's
compiled tick) both engines give the same golden record, score and outcome at every tick; the
Zelda golden traces of the Java engine replay through it; and GVGAI's own zelda.txt gives the
same where the corpus is present (``GVGAI_VGDL_DIR``).
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
OWN_ZELDA = registered_game("zelda").description
ROOT = HERE.parents[1]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"


def own_zelda() -> VGDLGame:
    return VGDLGame.from_file(OWN_ZELDA, name="vgdl:zelda")


def generated(count_per_d: int) -> list[Level]:
    return [generate_level("zelda", d / 4, seed) for d in range(5) for seed in range(count_per_d)]


# Small levels, some without a border (sprites may leave their screen), to batch with full-size ones.
SMALL_LEVELS = (
    ("A.2", "+.g", "1.."),
    ("w1w..", "A.+.g", "..3.."),
    ("wwwwww", "wA.2+w", "w1..gw", "wwwwww"),
    ("+A1", "g.3"),
)


def small_levels() -> list[Level]:
    return [Level("zelda", rows, name=f"small{index}") for index, rows in enumerate(SMALL_LEVELS)]


def without_monsters(level: Level) -> Level:
    """``level`` with its monsters replaced by floor: the avatar lives long enough to walk about,
    take the key and open the door."""
    rows = tuple(row.translate(str.maketrans("123", "...")) for row in level.rows)
    return Level(level.game, rows, name=f"{level.name}-calm")


def assert_same_play(game: VGDLGame, levels: list[Level], ticks: int, compiled: bool, seed: int = 0) -> dict:
    """Tick ``game`` and the hand-written Zelda side by side on random actions; every env's golden
    record must agree at every tick. ``compiled`` ticks ``game`` through the engine's compiled tick
    (the hand-written one ticks eagerly: its compiled tick is held to its eager one in
    tests/engine). Returns what happened, for the callers' coverage checks."""
    zelda = get_game("zelda")
    seeds = torch.arange(len(levels)) * 7919 + seed
    mine, theirs = game.compile(levels, seeds, "cpu"), zelda.compile(levels, seeds, "cpu")
    tick_mine = engine_tick(game) if compiled else game.tick
    tick_theirs = zelda.tick
    generator = torch.Generator().manual_seed(seed)
    seen = {"withkey": 0, "win": 0, "lose": 0, "kills": 0}
    for step in range(ticks):
        action = torch.randint(0, game.num_actions, (len(levels),), generator=generator)
        tick_mine(mine, action)
        tick_theirs(theirs, action)
        for key in ("score", "won", "lost"):
            assert torch.equal(mine.get(key), theirs.get(key)), f"{key} differs at tick {step}"
        for index in range(len(levels)):
            expected, actual = zelda.snapshot(theirs, index), game.snapshot(mine, index)
            assert actual == expected, f"{levels[index].name} at tick {step}:\n{expected}\n{actual}"
    fresh = game.compile(levels, seeds, "cpu")  # the tick writes its fields back unchecked
    for key in fresh.keys(True, True):
        assert (mine.get(key).dtype, mine.get(key).shape) == (fresh.get(key).dtype, fresh.get(key).shape), key
    for index in range(len(levels)):
        record = game.snapshot(mine, index)
        seen["withkey"] += record["avatar"] is not None and record["avatar"]["type"] == "withkey"
        seen["win"] += record["status"] == "win"
        seen["lose"] += record["status"] == "lose"
    seen["kills"] = int((mine.get("score") >= 2).sum())
    # the observation too: the same tiles, channel for channel (the orders of the types differ)
    channels = [game.tile_types.index(name) for name in zelda.tile_types]
    assert torch.equal(render_tiles(game, mine)[:, channels], render_tiles(zelda, theirs))
    return seen


@pytest.mark.skipif(not STRUCTURE.is_file(), reason=f"Java's parse ({STRUCTURE}) is not here")
def test_own_description_parses_as_java_parses_gvgai_zelda():
    rows = [json.loads(line) for line in STRUCTURE.read_text().splitlines() if line.strip()]
    java = next(row for row in rows if Path(row["file"]).name == "zelda.txt")
    game = parse_file(OWN_ZELDA)
    assert list(game.sprite_order) == java["sprite_order"]
    assert [[pair.first, pair.second, len(pair.effects)] for pair in game.pairs] == java["pairs"]
    assert list(game.eos) == java["eos"]
    assert {name: list(sprite.subtypes) for name, sprite in game.types.items()} == java["subtypes"]


def test_generic_zelda_equals_the_hand_written_batched_eager():
    levels = human_levels("zelda") + generated(2) + small_levels()
    assert len({(level.height, level.width) for level in levels}) > 1  # sizes differ in the batch
    assert_same_play(own_zelda(), levels, ticks=200, compiled=False)


def test_generic_zelda_equals_the_hand_written_batched_compiled():
    calm = [without_monsters(level) for level in human_levels("zelda")]
    levels = human_levels("zelda") + generated(1) + small_levels() + calm
    seen = assert_same_play(own_zelda(), levels, ticks=120, compiled=True, seed=1)
    assert seen["lose"] > 0
    tick = engine_tick(own_zelda())
    assert isinstance(tick, CompiledTick) and tick.failed is None  # it ran compiled


def crowded(level: Level, every: int) -> Level:
    """``level`` with a monster on every ``every``-th floor cell (kinds in turn)."""
    cells = [(r, c) for r, row in enumerate(level.rows) for c, ch in enumerate(row) if ch == "."]
    rows = [list(row) for row in level.rows]
    for index, (r, c) in enumerate(cells[::every]):
        rows[r][c] = "123"[index % 3]
    return Level(level.game, tuple("".join(row) for row in rows), name=f"{level.name}-crowded")


def test_crowded_generic_zelda_ticks_eagerly_and_equals_the_hand_written():
    levels = [crowded(level, 3) for level in human_levels("zelda")[:2]]
    game = own_zelda()
    state = game.compile(levels, torch.arange(2), "cpu")
    assert state.get("enemy").batch_size[1] > 16 and game.host_arguments(state) == {"crowded": True}
    assert_same_play(game, levels, ticks=60, compiled=True, seed=4)


def test_generic_zelda_takes_keys_and_opens_doors_as_the_hand_written():
    # calm levels: a long random walk that takes the key (transformTo) and opens the door (kill, win)
    levels = [without_monsters(level) for level in human_levels("zelda") + generated(4) + small_levels()]
    seen = assert_same_play(own_zelda(), levels, ticks=200, compiled=False, seed=2)
    assert seen["withkey"] + seen["win"] > 0


@pytest.mark.parametrize("index", [3, 6])  # a human level, a small one without a border
def test_generic_zelda_alone(index):
    level = (human_levels("zelda") + small_levels())[index]
    assert_same_play(own_zelda(), [level], ticks=100, compiled=False, seed=index)


# batched, the replays compile a tick of their own (20 s): make test keeps them alone
@pytest.mark.parametrize(
    "batched", [False, pytest.param(True, marks=pytest.mark.slow)], ids=["alone", "batched"]
)
@pytest.mark.parametrize("path", golden_files("zelda"), ids=lambda p: p.stem)
def test_generic_zelda_replays_gvgai_traces(path, batched):
    assert_replays(path, batched, own_zelda())


@pytest.mark.skipif(
    not (GAMES / "zelda.txt").is_file(), reason=f"GVGAI's zelda.txt is not in {GAMES}; set GVGAI_VGDL_DIR"
)
def test_gvgai_zelda_description_equals_the_hand_written():
    game = VGDLGame.from_file(GAMES / "zelda.txt")
    levels = human_levels("zelda") + generated(1) + [without_monsters(human_levels("zelda")[1])]
    assert_same_play(game, levels, ticks=200, compiled=False, seed=3)
    assert_replays(golden_files("zelda")[0], True, game)


@pytest.mark.slow
@pytest.mark.parametrize("compiled", [False, True], ids=["eager", "compiled"])
def test_generic_zelda_long_random_play(compiled):
    levels = human_levels("zelda") + generated(6) + small_levels()
    levels += [without_monsters(level) for level in levels[:12]]
    for seed in range(3):
        assert_same_play(own_zelda(), levels, ticks=600, compiled=compiled, seed=10 + seed)
