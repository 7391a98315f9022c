"""Replay a golden trace of the real GVGAI engine through our engine, tick by tick.

A trace is replayed alone, and batched between two human levels of the game (other sizes than
most trace levels, which are small and often have no border): a level must play the same
whatever it is batched with, so both replays must match the Java recording.
"""

from __future__ import annotations

import json
from pathlib import Path

import torch

from gvgai_pcg.engine.compiled import engine_tick
from gvgai_pcg.games import Game, get_game
from gvgai_pcg.levels import Level, human_level

GOLDEN_DIR = Path(__file__).parent / "golden"


def golden_files(game: str) -> list[Path]:
    return sorted(GOLDEN_DIR.glob(f"{game}_*.json"))


def replay(path: Path, batched: bool = False, game: Game | None = None) -> list[tuple[dict, dict]]:
    """(expected, actual) snapshot pairs for every recorded tick of the trace at ``path``; with
    ``batched`` the trace's env is the middle one of three, beside human levels 0 and 1 (which get
    the same actions). ``game`` replaces the trace's registered game (another engine of it)."""
    trace = json.loads(path.read_text())
    game = game or get_game(trace["game"])
    level = Level(trace["game"], tuple(trace["level"]))  # may exceed the full size on purpose
    levels, seeds, index = [level], [12345], 0
    if batched:
        levels = [human_level(trace["game"], 0), level, human_level(trace["game"], 1)]
        seeds, index = [1, 12345, 2], 1
    state = game.compile(levels, torch.tensor(seeds), torch.device("cpu"))
    actions = ["NIL", *trace["actions"]]
    tick = engine_tick(game)  # compiled where the engine compiles the game
    pairs = []
    for expected in trace["ticks"]:
        action = game.actions.index(actions[expected["tick"]])
        tick(state, torch.full((len(levels),), action))
        actual = game.snapshot(state, index)
        expected = {key: expected[key] for key in ("tick", "score", "status", "avatar", "sprites")}
        pairs.append((expected, actual))
    return pairs


def assert_replays(path: Path, batched: bool = False, game: Game | None = None) -> None:
    where = "batched" if batched else "alone"
    for expected, actual in replay(path, batched, game):
        assert actual == expected, (
            f"{path.name} ({where}), tick {expected['tick']}:\nexpected {expected}\nactual   {actual}"
        )
