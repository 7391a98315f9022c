"""Six GVGAI corpus games the generic step runs with no feature class of their own (camelRace,
racebet, racebet2, painter, infection, zenpuzzle), and seven of the Sokoban family (bait,
colourescape, escape, realsokoban, sokoban, thesnowman, watergame): on their five human levels,
batched (levels of different sizes in one state), the step gives each env what it gives the level
played alone, eager and through the engine's compiled tick, on random actions. Java's traces of
these games are checked with ``gvgai-pcg vgdl trace`` (the ``traces`` recordings); here the engine
is held to itself. Needs GVGAI's VGDL files (``GVGAI_VGDL_DIR``)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
import torch

from gvgai_pcg.engine.compiled import CompiledTick, engine_tick
from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.engine.trace import read_level

ROOT = Path(__file__).parents[2]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
SIX = ("camelRace", "racebet", "racebet2", "painter", "infection", "zenpuzzle")
# the Sokoban family's games the generic step runs (bounceForward, killBoth, undoAll)
SOKOBAN = ("bait", "colourescape", "escape", "realsokoban", "sokoban", "thesnowman", "watergame")
TICKS = 60

needs_corpus = pytest.mark.skipif(
    not (GAMES / "camelRace.txt").is_file(),
    reason=f"GVGAI's VGDL files are not in {GAMES}; set GVGAI_VGDL_DIR",
)


def human_levels(game: str) -> list[Level]:
    return [read_level(GAMES / f"{game}_lvl{index}.txt", game) for index in range(5)]


def play(
    vgdl: VGDLGame, levels: list[Level], actions: torch.Tensor, seeds: torch.Tensor, compiled: bool
) -> list[list[dict]]:
    """Per tick, every env's golden record; ``actions`` ``[T, B]``."""
    state = vgdl.compile(levels, seeds, "cpu")
    tick = engine_tick(vgdl) if compiled else vgdl.tick
    records = []
    for action in actions:
        tick(state, action)
        records.append([vgdl.snapshot(state, index) for index in range(len(levels))])
    return records


def random_actions(vgdl: VGDLGame, envs: int, seed: int) -> torch.Tensor:
    generator = torch.Generator().manual_seed(seed)
    actions = torch.randint(len(vgdl.actions), (TICKS, envs), generator=generator)
    actions[0] = 0  # the reset tick: NIL
    return actions


@needs_corpus
@pytest.mark.slow  # 20-60 s of compiling each
@pytest.mark.parametrize("game", SIX + SOKOBAN)
def test_batched_eager_and_compiled_play_equals_each_level_alone(game):
    vgdl = VGDLGame.from_file(GAMES / f"{game}.txt")
    levels = human_levels(game)
    actions = random_actions(vgdl, len(levels), seed=len(game))
    seeds = torch.arange(len(levels)) * 7919
    batched = play(vgdl, levels, actions, seeds, compiled=False)
    assert batched[0] != batched[-1]  # something happened
    for index, level in enumerate(levels):
        alone = play(vgdl, [level], actions[:, index : index + 1], seeds[index : index + 1], compiled=False)
        assert [records[index] for records in batched] == [records[0] for records in alone], level.name
    assert play(vgdl, levels, actions, seeds, compiled=True) == batched
    tick = engine_tick(vgdl)
    assert isinstance(tick, CompiledTick) and tick.failed is None  # it ran compiled
