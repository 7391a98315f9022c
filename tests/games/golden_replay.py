"""Replay a golden trace of the real GVGAI engine through our engine, tick by tick."""

from __future__ import annotations

import json
from pathlib import Path

import torch

from gvgai_pcg.games import get_game
from gvgai_pcg.levels import Level

GOLDEN_DIR = Path(__file__).parent / "golden"


def golden_files(game: str) -> list[Path]:
    return sorted(GOLDEN_DIR.glob(f"{game}_*.json"))


def replay(path: Path) -> list[tuple[dict, dict]]:
    """(expected, actual) snapshot pairs for every recorded tick of the trace at ``path``."""
    trace = json.loads(path.read_text())
    game = get_game(trace["game"])
    level = Level(trace["game"], tuple(trace["level"]))  # may exceed the full size on purpose
    state = game.compile([level], torch.tensor([12345]), torch.device("cpu"))
    actions = ["NIL", *trace["actions"]]
    pairs = []
    for expected in trace["ticks"]:
        action = game.actions.index(actions[expected["tick"]])
        game.tick(state, torch.tensor([action]))
        actual = game.snapshot(state, 0)
        expected = {key: expected[key] for key in ("tick", "score", "status", "avatar", "sprites")}
        pairs.append((expected, actual))
    return pairs


def assert_replays(path: Path) -> None:
    for expected, actual in replay(path):
        assert actual == expected, (
            f"{path.name}, tick {expected['tick']}:\nexpected {expected}\nactual   {actual}"
        )
