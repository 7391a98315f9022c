"""A toy game defined outside the package, as a user would write one: walk to the goal.

Rules: the avatar ``A`` moves one cell per tick (NIL, LEFT, RIGHT, DOWN, UP) unless a wall ``w``
or the screen's edge is in the way; stepping on the goal ``g`` scores 1 and wins. Its level
format, one level, a generator with a difficulty knob (more walls) and the ``GameSpec`` that
names them: all ``gvgai_pcg`` needs to run it (docs/howto/add-a-game.md walks through the same
code).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import torch
from tensordict import TensorDict

from gvgai_pcg.games import Game, GameSpec, GridLayer, LevelFormat, SpriteArt, WinNeed
from gvgai_pcg.games.base import avatar_cell, char_grid, common_state, golden_record, single_sprite_layer
from gvgai_pcg.games.geometry import CELL, NONE, direction_dx, direction_dy
from gvgai_pcg.levels import Level

LEVEL_TEXT = """\
wwwwwww
wA...gw
w.www.w
w.....w
wwwwwww
"""


def toy_format(name: str = "toy") -> LevelFormat:
    return LevelFormat(name, "w.gA", "A", height=5, width=7, win_needs=(WinNeed("g", 1, "goal (g)"),))


class Walk(Game):
    """Walk to the goal; one avatar, static walls and goal."""

    actions = ("NIL", "LEFT", "RIGHT", "DOWN", "UP")
    tile_types = ("wall", "goal", "avatar")
    art = {
        "floor": SpriteArt((40, 40, 40)),
        "wall": SpriteArt((110, 90, 70)),
        "goal": SpriteArt((250, 210, 0), "frame"),
        "avatar": SpriteArt((250, 250, 250), "circle"),
    }

    def compile(self, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device) -> TensorDict:
        batch = len(levels)
        x, y = avatar_cell(levels, "A")
        avatar = TensorDict(
            {"x": x, "y": y, "alive": torch.ones(batch, dtype=torch.bool)}, batch_size=[batch]
        )
        state = {
            **common_state(levels, seeds, device),
            "wall": char_grid(levels, "w", device),
            "goal": char_grid(levels, "g", device),
            "avatar": avatar.to(device),
        }
        return TensorDict(state, batch_size=[batch], device=device)

    def tick(self, state: TensorDict, action: torch.Tensor) -> None:
        avatar, wall, goal = state.get("avatar"), state.get("wall"), state.get("goal")
        running = ~(state.get("won") | state.get("lost"))
        direction = torch.where((action > 0) & running, action - 1, torch.full_like(action, NONE))
        x = avatar.get("x") + CELL * direction_dx(direction)
        y = avatar.get("y") + CELL * direction_dy(direction)
        column, row = x.div(CELL, rounding_mode="floor"), y.div(CELL, rounding_mode="floor")
        envs = torch.arange(len(action), device=action.device)
        inside = (column >= 0) & (column < state.get("width")) & (row >= 0) & (row < state.get("height"))
        column, row = column.clamp(0, wall.shape[2] - 1), row.clamp(0, wall.shape[1] - 1)
        moves = inside & ~wall[envs, row, column]
        avatar.get("x").copy_(torch.where(moves, x, avatar.get("x")))
        avatar.get("y").copy_(torch.where(moves, y, avatar.get("y")))
        column = avatar.get("x").div(CELL, rounding_mode="floor")
        row = avatar.get("y").div(CELL, rounding_mode="floor")
        reached = goal[envs, row, column] & running
        goal.index_put_((envs, row, column), goal[envs, row, column] & ~reached)
        state.get("score").add_(reached.long())
        state.get("won").logical_or_(reached)
        state.get("tick").add_(1)

    def layers(self, state: TensorDict) -> list:
        return [
            GridLayer("wall", state.get("wall")),
            GridLayer("goal", state.get("goal")),
            single_sprite_layer("avatar", state.get("avatar")),
        ]

    def snapshot(self, state: TensorDict, index: int) -> dict:
        s = state[index]
        avatar = {"type": "avatar", "x": s.get(("avatar", "x")).item(), "y": s.get(("avatar", "y")).item()}
        sprites = [["goal", CELL * c, CELL * r] for r, c in s.get("goal").nonzero().tolist()]
        return golden_record(s, avatar, sprites)

    def max_score(self, level: Level) -> int:
        return min(1, level.count("g"))


def generate(difficulty: float, seed: int, name: str = "toy") -> Level:
    """A 7x5 room with the avatar, the goal and ``round(4 d)`` walls in random inner cells."""
    rng = np.random.default_rng(seed)
    grid = np.full((5, 7), ".")
    grid[[0, -1], :] = "w"
    grid[:, [0, -1]] = "w"
    inner = [(r, c) for r in range(1, 4) for c in range(1, 6)]
    cells = rng.choice(len(inner), size=2 + round(4 * difficulty), replace=False)
    for char, k in zip("Ag" + "w" * 4, cells, strict=False):
        grid[inner[k]] = char
    rows = ["".join(row) for row in grid]
    return Level(name, rows, name=f"{name}_d{difficulty:g}_s{seed}", seed=seed)


SPEC = GameSpec(name="toy", title="Toy", level_format=toy_format(), rules=Walk, generator=generate)


class WalkAgain(Walk):
    """The same rules under a second name (a game class belongs to one game)."""


def generate_again(difficulty: float, seed: int) -> Level:
    return generate(difficulty, seed, name="toyagain")


# A second toy game, as an installed package would offer it through the entry-point group.
PLUGIN_SPEC = GameSpec(
    name="toyagain",
    title="ToyAgain",
    level_format=toy_format("toyagain"),
    rules=WalkAgain,
    generator=generate_again,
)
