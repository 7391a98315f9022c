"""Scripted Zelda scenarios: inline levels, action scripts, and scripted monster directions."""

from __future__ import annotations

import torch

from gvgai_pcg.games import get_game
from gvgai_pcg.games import rng as rng_module
from gvgai_pcg.levels import Level

ZELDA = get_game("zelda")
ACTION = {name: i for i, name in enumerate(ZELDA.actions)}


def script_directions(monkeypatch, choose) -> None:
    """Make every RandomNPC draw ``choose(tick, slot)`` (a direction code) instead of a random one.

    ``choose`` gets the ``[B]`` tick tensor and the ``[K]`` slot tensor and returns ``[B, K]``.
    """

    def scripted(seed, tick, slot, stream, high):
        return choose(tick.unsqueeze(-1), slot.unsqueeze(0)).expand(tick.shape[0], slot.shape[0])

    monkeypatch.setattr(rng_module, "randint", scripted)


def play(rows: list[str], actions: list[str], seed: int = 0) -> list[dict]:
    """Snapshots after the reset tick (index 0) and after each action (index k = tick k)."""
    state = ZELDA.compile([Level("zelda", tuple(rows))], torch.tensor([seed]), torch.device("cpu"))
    snapshots = []
    for action in ["NIL", *actions]:
        ZELDA.tick(state, torch.tensor([ACTION[action]]))
        snapshots.append(ZELDA.snapshot(state, 0))
    return snapshots


def sprite_at(snapshot: dict, kind: str) -> list[tuple[int, int]]:
    """Cells (column, row) of every sprite of ``kind`` in a snapshot."""
    return [(x // 10, y // 10) for name, x, y in snapshot["sprites"] if name == kind]
