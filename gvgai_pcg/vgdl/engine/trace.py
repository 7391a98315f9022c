"""A level played through the generic step, recorded tick by tick in the golden traces' format.

The golden traces (docs/spec/golden-traces.md) are Java's recordings: tick 0 plays NIL (the
Gym's reset), action k is played in tick k, and the recording stops at the tick the game ends
in or after the last action. Each tick holds its number, action, score, status, the avatar
(``null`` when there is none) and the sprites sorted by type, y, x. Here every type but the
avatar's is listed unless ``exclude`` names it (the golden traces leave out the still decoration,
e.g. Zelda's ``wall`` and ``floor``).
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from pathlib import Path

import torch

from gvgai_pcg.games.base import golden_record
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.level import decode
from gvgai_pcg.vgdl.engine.game import VGDLGame

RESET_ACTION = "NIL"


def read_level(path: str | Path, game: str) -> Level:
    """A level file as rows, of any size (golden levels may be larger or smaller than a study
    game's); the characters are checked against the description when the level is compiled."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as error:
        raise ValueError(f"cannot read level {path}: {error.strerror}") from None
    text = decode(data, str(path)).replace("\r\n", "\n").replace("\r", "\n").rstrip("\n")
    rows = text.split("\n")
    if not text.strip():
        raise ValueError(f"{path}: empty level")
    ragged = next((r for r, row in enumerate(rows) if len(row) != len(rows[0])), None)
    if ragged is not None:
        raise ValueError(
            f"{path}: row {ragged + 1} has {len(rows[ragged])} characters, row 1 has {len(rows[0])}"
        )
    return Level(game, tuple(rows), name=str(path))


def check_trace_input(game: VGDLGame, actions: Sequence[str], exclude: Collection[str]) -> None:
    """Refuse, in one line naming it, an action the game does not have or a type it does not
    describe."""
    for action in actions:
        if action not in game.actions:
            raise ValueError(f"unknown action {action!r}: {game.name} has {', '.join(game.actions)}")
    for name in exclude:
        if name not in game.layout.plan.types:
            raise ValueError(f"--exclude: {game.name} has no sprite type {name!r}")


def play_trace(
    game: VGDLGame, level: Level, actions: Sequence[str], seed: int = 0, exclude: Collection[str] = ()
) -> list[dict]:
    """The ticks of ``level`` played with ``actions`` (NIL first), eagerly on the CPU."""
    check_trace_input(game, actions, exclude)
    layout = game.layout
    shown = [name for name in layout.types if name not in layout.avatars and name not in exclude]
    state = game.compile([level], torch.tensor([seed]), torch.device("cpu"))
    ticks = []
    for action in (RESET_ACTION, *actions):
        game.tick(state, torch.tensor([game.actions.index(action)]))
        s, record = state[0], game.snapshot(state, 0)
        tick = golden_record(s, record["avatar"], game.sprites(s, shown))
        ticks.append({"tick": tick["tick"], "action": action} | tick)
        if tick["status"] != "running":
            break
    return ticks
