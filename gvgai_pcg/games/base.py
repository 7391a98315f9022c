"""The contract every game implements, and the compile helpers they share.

A game is a set of rules over a batched state (a ``TensorDict`` with batch size ``[B]``):
static tiles as ``[B, H, W]`` bool grids, moving sprites as entity tables (nested
TensorDicts with batch size ``[B, K]`` and an ``alive`` mask). The env grows each table on its
own (empty slots, to at least two, in powers of two: ``gvgai_pcg.envs.states``), so a table whose
slots belong to another's slots (Solarfox's shots, a block per enemy) is nested in that table,
with leaves ``[B, K, ...]``, and grows with it. Every state carries the common
entries ``seed``, ``tick``, ``score``, ``won``, ``lost`` and each env's own screen size in cells,
``height`` and ``width`` (all ``[B]``). ``tick`` runs one game cycle for all B environments with
tensor ops only (RULES.md §1.3); the engine never loops over environments or sprites in Python.

Levels of one batch may differ in size. The grids take the largest size, and a smaller level is
padded with ``OUTSIDE`` cells: beyond its screen, where nothing is (no wall, no sprite), so a level
behaves the same whatever it is batched with. Every edge test (EOS, wrapAround) and every
off-grid test uses the env's own ``height`` and ``width``, never the batch's grid.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

import numpy as np
import torch
from tensordict import TensorDict

from gvgai_pcg._private_apis import unchecked_tensordict
from gvgai_pcg.games.geometry import CELL
from gvgai_pcg.games.spec import StepFacts
from gvgai_pcg.levels import Level, LevelFormat, level_format
from gvgai_pcg.levels.padding import pad_rows

# A cell beyond a level's screen, where padding grows the level to a batch's grid. No legend has
# this character (and Level.parse refuses it), so nothing is there: no wall, no sprite.
OUTSIDE = " "


@dataclass(frozen=True)
class GridLayer:
    """Static sprites of one type: one per set cell of ``cells`` (``[B, H, W]`` bool)."""

    name: str
    cells: torch.Tensor


@dataclass(frozen=True)
class SpriteLayer:
    """Moving sprites of one type at pixel positions ``x, y`` (``[B, K]``) where ``present``.

    ``variant`` (``[B, K]`` int, optional) picks one of the type's images, e.g. the facing of an
    oriented avatar. ``row`` (``[B, K]`` int32, optional) is the grid row of every slot, for
    sprites that stay cell-aligned in y inside the grid (lanes): ``tiles`` then reads it instead
    of working the row out from ``y``.
    """

    name: str
    x: torch.Tensor
    y: torch.Tensor
    present: torch.Tensor
    variant: torch.Tensor | None = None
    row: torch.Tensor | None = None


Layer = GridLayer | SpriteLayer


def single_sprite_layer(
    name: str, table: TensorDict, present: str | torch.Tensor = "alive", oriented: bool = False
) -> SpriteLayer:
    """The layer of a sprite every env has at most one of (the avatar, a sword), from its ``[B]``
    table: ``present`` names the table's presence entry or is a ``[B]`` mask; an oriented sprite
    is drawn by its ``ori``."""
    mask = table.get(present) if isinstance(present, str) else present
    variant = table.get("ori").unsqueeze(-1) if oriented else None
    return SpriteLayer(
        name, table.get("x").unsqueeze(-1), table.get("y").unsqueeze(-1), mask.unsqueeze(-1), variant
    )


@dataclass(frozen=True)
class SpriteArt:
    """Our own tile art for a sprite type: a colour and a shape (see ``gvgai_pcg.games.render``)."""

    color: tuple[int, int, int]
    shape: str = "square"
    oriented: bool = False


class Game(ABC):
    """One GVGAI game: its legend, action set, batched state and tick."""

    name: ClassVar[str]
    actions: ClassVar[tuple[str, ...]]
    # Observation channels of ``tiles``, one per sprite type that matters (decoration left out).
    tile_types: ClassVar[tuple[str, ...]]
    art: ClassVar[dict[str, SpriteArt]]
    # True where the reset tick (tick 0, NIL) draws nothing from the RNG, by the rules, so the
    # state after it is the same whatever the episode seed: an env then keeps a recurring level
    # as it stands after its reset tick, with its first observation, and a replay of it runs no
    # tick (gvgai_pcg.envs.level_bank). False (the safe default) where tick 0 may draw.
    seed_free_reset_tick: ClassVar[bool] = False

    @property
    def step_facts(self) -> StepFacts:
        """Whether and where the tick compiles, and its miscompile opt-outs: the game's
        ``GameSpec.step_facts`` (a game class outside the registry may set its own)."""
        from gvgai_pcg.games.registry import find_game_spec

        spec = find_game_spec(self.name)
        return StepFacts() if spec is None else spec.step_facts

    @property
    def level_format(self) -> LevelFormat:
        return level_format(self.name)

    @property
    def num_actions(self) -> int:
        return len(self.actions)

    @abstractmethod
    def compile(self, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device) -> TensorDict:
        """The initial state of ``len(levels)`` envs, before the reset tick (``tick == -1``). Levels
        of different sizes (or padded with :func:`pad_level`) share the largest grid, each keeping
        its own screen (see the module docstring)."""

    @abstractmethod
    def tick(self, state: TensorDict, action: torch.Tensor) -> None:
        """Advance every env of ``state`` by one game cycle with ``action`` (``[B]`` int), in place.

        A tick may take keyword arguments from :meth:`host_arguments`; called without them, it
        works them out itself."""

    def host_arguments(self, state: TensorDict) -> dict[str, object]:
        """What the next tick takes from outside a compiled graph, as keyword arguments: choices
        for the whole batch (bools, read on the host; a graph gets each as a constant, one graph
        per combination met), and tables made once outside the graph (tensors, graph inputs; a
        graph with dynamic shapes would rebuild them every call)."""
        return {}

    def reset_tick(self, state: TensorDict) -> None:
        """The reset tick (RULES.md §1.8: tick 0, with NIL) of freshly compiled envs, in place.

        Every partial reset runs it on a small batch, where a tick costs its few hundred ops
        whatever the batch size. A game whose tick 0 does little may do just that little, as
        long as the state ends up exactly as ``tick`` with NIL leaves it (tested per game).
        """
        nil = torch.zeros(state.batch_size[0], dtype=torch.int64, device=state.device)
        self.tick(state, nil)

    @abstractmethod
    def layers(self, state: TensorDict) -> list[Layer]:
        """What is drawn, in drawing order (the avatar last)."""

    @abstractmethod
    def snapshot(self, state: TensorDict, index: int) -> dict:
        """Env ``index`` in the golden-trace format (``docs/spec/golden-traces.md``)."""

    @abstractmethod
    def max_score(self, level: Level) -> int:
        """The highest score the rules allow on ``level`` (RULES.md §4.6, 5.8, 6.6, 7.6)."""


def golden_record(state: TensorDict, avatar: dict | None, sprites: list[list]) -> dict:
    """One env's snapshot in the golden-trace format: ``state`` is that env's (unbatched) state;
    ``sprites`` (``[type, x, y]`` entries) are sorted by type name, then y, then x."""
    status = "win" if state.get("won").item() else "lose" if state.get("lost").item() else "running"
    return {
        "tick": state.get("tick").item(),
        "score": state.get("score").item(),
        "status": status,
        "avatar": avatar,
        "sprites": sorted(sprites, key=lambda item: (item[0], item[2], item[1])),
    }


def common_state(
    levels: Sequence[Level], seeds: torch.Tensor, device: torch.device
) -> dict[str, torch.Tensor]:
    """The entries every game state has, for a fresh episode (the reset tick makes ``tick`` 0)."""
    batch = seeds.shape[0]
    heights, widths = zip(*map(screen_size, levels), strict=True)
    return {
        "seed": seeds.to(device=device, dtype=torch.int64).clone(),  # never shared with the caller
        "tick": torch.full((batch,), -1, dtype=torch.int64, device=device),
        "score": torch.zeros(batch, dtype=torch.int64, device=device),
        "won": torch.zeros(batch, dtype=torch.bool, device=device),
        "lost": torch.zeros(batch, dtype=torch.bool, device=device),
        "height": torch.tensor(heights, dtype=torch.int64, device=device),
        "width": torch.tensor(widths, dtype=torch.int64, device=device),
    }


def on_device(device: torch.device | str, values: dict, batch_size: Sequence[int]) -> TensorDict:
    """``TensorDict(values, batch_size, device)`` for a ``compile``, unchecked: it builds every
    entry (tensors and tables made by ``on_device``) at its batch size, and a reset compiles a
    level or two at a time, where TensorDict's checks and ``.to`` cost as much as the entries
    (one level: Solarfox 477 to 316 us, Frogs 991 to 774 us)."""
    device = torch.device(device)
    moved = {
        key: value if isinstance(value, TensorDict) else value.to(device) for key, value in values.items()
    }
    return unchecked_tensordict(moved, torch.Size(batch_size), device)


def screen_size(level: Level) -> tuple[int, int]:
    """(height, width) in cells of ``level``'s own screen: its grid without the ``OUTSIDE``
    rows at the bottom and columns at the right that :func:`pad_level` added."""
    height = sum(1 for row in level.rows if not row.startswith(OUTSIDE))
    return height, len(level.rows[0].rstrip(OUTSIDE))


def open_border(closed: torch.Tensor, height: torch.Tensor, width: torch.Tensor) -> torch.Tensor:
    """``[B]`` bool: whether some cell on the border of each env's own screen (``height`` x
    ``width`` cells, ``[B]``) is not ``closed`` (``[B, H, W]`` bool, e.g. the walls). In a game
    whose walls stop everything that moves, only such a level lets sprites leave its screen."""
    _, rows, columns = closed.shape
    r = torch.arange(rows, device=closed.device).view(1, rows, 1)
    c = torch.arange(columns, device=closed.device).view(1, 1, columns)
    h, w = height.view(-1, 1, 1), width.view(-1, 1, 1)
    border = (r < h) & (c < w) & ((r == 0) | (r == h - 1) | (c == 0) | (c == w - 1))
    return (border & ~closed).flatten(1).any(-1)


def char_codes(levels: Sequence[Level]) -> np.ndarray:
    """``[B, H, W]`` uint8: the character codes of ``levels``, smaller ones padded with ``OUTSIDE``
    to the largest height and width (shared: do not modify)."""
    return _char_codes(tuple(levels))


@lru_cache(maxsize=4)  # a compile looks up the same levels once per sprite type
def _char_codes(levels: tuple[Level, ...]) -> np.ndarray:
    height, width = max(level.height for level in levels), max(level.width for level in levels)
    levels = tuple(pad_level(level, height, width) for level in levels)
    text = "".join("".join(level.rows) for level in levels).encode("utf-32-le")
    codes = np.frombuffer(text, dtype=np.uint32)
    # Characters beyond 255 belong to no legend: they read as code 0, which none uses either.
    return np.where(codes < 256, codes, 0).astype(np.uint8).reshape(len(levels), height, width)


def char_grid(levels: Sequence[Level], chars: str, device: torch.device) -> torch.Tensor:
    """``[B, H, W]`` bool: where each level holds one of ``chars``."""
    wanted = np.zeros(256, dtype=bool)
    wanted[list(chars.encode("latin-1"))] = True
    return torch.from_numpy(wanted[char_codes(levels)]).to(device)


def char_entities(
    levels: Sequence[Level], kinds: dict[str, int], device: torch.device, capacity: int | None = None
) -> TensorDict:
    """An entity table (batch ``[B, K]``) of the sprites placed by ``kinds`` (char -> kind code).

    Slots follow ``(kind code, row-major order)``, which is the order in which GVGAI processes a
    type group whose subtypes are declared in that order. ``K`` is the largest count in the batch
    (or ``capacity``); unused slots have ``alive`` false.
    """
    codes = char_codes(levels)
    batch, height, width = codes.shape
    cells = height * width
    kind_of = np.full(256, -1, dtype=np.int64)
    for ch, code in kinds.items():
        kind_of[ord(ch)] = code
    kind = kind_of[codes].reshape(batch, cells)
    # Each sprite's sort key (kind code, then cell); empty cells sort last.
    empty = (max(kinds.values(), default=0) + 1) * cells
    keys = np.where(kind >= 0, kind * cells + np.arange(cells), empty)
    size = max(int((kind >= 0).sum(1).max(initial=0)), capacity or 0)
    keys = np.sort(keys, axis=1)[:, :size]
    if keys.shape[1] < size:
        keys = np.pad(keys, ((0, 0), (0, size - keys.shape[1])), constant_values=empty)
    alive = keys < empty
    cell = np.where(alive, keys % cells, 0)
    table = {
        "x": torch.from_numpy(CELL * (cell % width)),
        "y": torch.from_numpy(CELL * (cell // width)),
        "kind": torch.from_numpy(np.where(alive, keys // cells, 0)),
        "alive": torch.from_numpy(alive),
    }
    return on_device(device, table, [batch, size])


def avatar_cell(levels: Sequence[Level], chars: str) -> tuple[torch.Tensor, torch.Tensor]:
    """Pixel position (x ``[B]``, y ``[B]``) of each level's avatar character."""
    cells = [next(level.find(ch)[0] for ch in chars if level.count(ch)) for level in levels]
    ys, xs = zip(*cells, strict=True)
    return CELL * torch.tensor(xs, dtype=torch.int64), CELL * torch.tensor(ys, dtype=torch.int64)


def pad_level(level: Level, height: int, width: int) -> Level:
    """``level`` grown to ``height x width`` with ``OUTSIDE`` rows at the bottom and columns at the
    right: cells beyond its screen, which hold nothing and keep its edge where it was (a level
    already that size is returned as is)."""
    rows = pad_rows(level.rows, height, width, OUTSIDE, level.name or "")
    if (level.height, level.width) == (height, width):
        return level
    return Level(level.game, tuple(rows), name=level.name, seed=level.seed)
