"""What every game's level editor shares (ACCEL's mutations): a mutable grid, picking a random cell
of some characters, and the retry loop that keeps only edits that leave the level valid.

An editor is ``edit(level, seed) -> Level`` (``GameSpec.editor``). Each game lists its edit kinds,
functions that change a ``Grid`` in place with a ``numpy`` generator and say whether they found
somewhere to act, and its ``BOUNDS``: the counts (monsters, walls, pills, logs per lane...) its
generator can place, derived from the generator's own constants. ``apply_edit`` draws a kind with
the seed, applies it and keeps the result only if it is still valid (``still_valid``) and no
further outside any bound than its parent (``keeps_bounds``). A draw that fails is followed by
another, up to ``ATTEMPTS``; when none succeeds the level comes back unchanged.

Why bounds: without them an editor is a random walk with no floor or ceiling (a Zelda level
kept without any selection gathers dozens of monsters in a few hundred generations), so what a
curriculum's buffer drifts to would say as much about the editor as about the curriculum's
score. Why a refused edit is redrawn rather than dropped: at a bound, the kinds that lead back
inside (or move things) stay as likely as before, so the editor keeps changing the level and
the walk reflects off the bound instead of stalling on it. An edit costs about two parses and
two runs of the game's checks (a millisecond or less; docs/generators.md, "Level editors").
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from gvgai_pcg.games.registry import check_seed, get_game_spec
from gvgai_pcg.levels.level import Level, LevelFormatError

Cell = tuple[int, int]
ATTEMPTS = 32  # edit draws tried before the level is given back unchanged


class Grid:
    """A level's characters as mutable rows; ``level()`` makes the edited ``Level``."""

    def __init__(self, level: Level) -> None:
        self.game = level.game
        self.cells = [list(row) for row in level.rows]
        self.height, self.width = level.height, level.width

    def __getitem__(self, cell: Cell) -> str:
        return self.cells[cell[0]][cell[1]]

    def __setitem__(self, cell: Cell, char: str) -> None:
        self.cells[cell[0]][cell[1]] = char

    def find(self, chars: str, where: Callable[[Cell], bool] | None = None) -> list[Cell]:
        """Every cell holding one of ``chars`` (and passing ``where``), in row-major order."""
        found = [(r, c) for r, row in enumerate(self.cells) for c, ch in enumerate(row) if ch in chars]
        return found if where is None else [cell for cell in found if where(cell)]

    def level(self) -> Level:
        """The edited level, without a name or seed: a curriculum gives it its identity."""
        return Level(self.game, tuple("".join(row) for row in self.cells))


EditKind = Callable[[Grid, np.random.Generator], bool]


def pick(rng: np.random.Generator, cells: list[Cell]) -> Cell | None:
    """A uniformly drawn cell of ``cells``; ``None`` when there is none."""
    return cells[int(rng.integers(len(cells)))] if cells else None


def choose(rng: np.random.Generator, chars: str) -> str:
    """One character of ``chars``, uniformly."""
    return chars[int(rng.integers(len(chars)))]


def place(
    grid: Grid, rng: np.random.Generator, char: str, on: str, where: Callable[[Cell], bool] | None = None
) -> bool:
    """Write ``char`` on a random cell holding one of ``on`` (and passing ``where``)."""
    cell = pick(rng, grid.find(on, where))
    if cell is None:
        return False
    grid[cell] = char
    return True


def move(
    grid: Grid,
    rng: np.random.Generator,
    chars: str,
    on: str,
    leave: str,
    where: Callable[[Cell], bool] | None = None,
) -> bool:
    """Move a random cell of ``chars`` onto a random cell of ``on`` (passing ``where``); the cell it
    left becomes ``leave``."""
    source = pick(rng, grid.find(chars))
    target = pick(rng, grid.find(on, where))
    if source is None or target is None:
        return False
    grid[target], grid[source] = grid[source], leave
    return True


def inner_box(grid: Grid) -> Callable[[Cell], bool]:
    """Whether a cell lies in the bounding box of the cells that are not wall: the part of a level
    inside its outer wall ring (and the generators' `w` frame), which editors keep off."""
    open_cells = [(r, c) for r, row in enumerate(grid.cells) for c, ch in enumerate(row) if ch != "w"]
    rows = [r for r, _ in open_cells]
    cols = [c for _, c in open_cells]
    top, bottom, left, right = min(rows), max(rows), min(cols), max(cols)
    return lambda cell: top <= cell[0] <= bottom and left <= cell[1] <= right


def distance(a: Cell, b: Cell) -> int:
    """Manhattan distance in cells."""
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def far_from(cells: Iterable[Cell], more_than: int) -> Callable[[Cell], bool]:
    """Whether a cell is more than ``more_than`` cells (Manhattan) from every one of ``cells``."""
    cells = list(cells)
    return lambda cell: all(distance(cell, other) > more_than for other in cells)


class Bound(Protocol):
    """A count an edited level is kept within; ``excess`` is how far outside it ``level`` is (0
    inside), so that a parent already outside (a human level, say) may still be edited, only
    never further out."""

    name: str

    def excess(self, level: Level) -> int: ...


@dataclass(frozen=True)
class CountBound:
    """How many cells hold one of ``chars``, in ``[low, high]``; with ``inner``, only the cells
    inside the level's outer wall ring (``inner_box``), so that the border walls are not counted."""

    name: str
    chars: str
    low: int
    high: int
    inner: bool = False

    def __post_init__(self) -> None:
        if not 0 <= self.low <= self.high:
            raise ValueError(f"bound {self.name!r}: expected 0 <= low <= high, got [{self.low}, {self.high}]")

    def count(self, level: Level) -> int:
        grid = Grid(level)
        return len(grid.find(self.chars, inner_box(grid) if self.inner else None))

    def excess(self, level: Level) -> int:
        have = self.count(level)
        return max(self.low - have, have - self.high, 0)


def keeps_bounds(parent: Level, child: Level, bounds: Sequence[Bound]) -> bool:
    """Whether ``child`` is no further outside any of ``bounds`` than ``parent`` (inside all of
    them where the parent was)."""
    return all(bound.excess(child) <= bound.excess(parent) for bound in bounds)


def out_of_bounds(level: Level, bounds: Sequence[Bound]) -> dict[str, int]:
    """The bounds ``level`` is outside of, each with its excess (empty: inside all of them)."""
    return {bound.name: excess for bound in bounds if (excess := bound.excess(level))}


# A uniform draw close below 1 for a generator's highest counts. Not the very largest float below
# 1: in ``14 d + 2 r`` that one rounds up to a whole number, a draw with a chance of 2^-53.
ALMOST_ONE = 1.0 - 2.0**-30
DIFFICULTY_GRID = tuple(i / 100 for i in range(101))  # the d at which a generator's range is read


def parameter_range(parameters: Callable[[float, Callable[[], float]], tuple], index: int) -> tuple[int, int]:
    """(lowest, highest) of a generator's ``parameters(d, r)[index]`` over d in [0, 1]: every
    uniform draw at 0 for the lowest and just below 1 for the highest. Exact for the counts the
    bounds use, which grow with every draw of ``r`` (the generators' formulas: counts are
    ``floor`` of products of terms that grow with their draws); d is read on a grid of 101."""
    low = min(parameters(d, lambda: 0.0)[index] for d in DIFFICULTY_GRID)
    high = max(parameters(d, lambda: ALMOST_ONE)[index] for d in DIFFICULTY_GRID)
    return int(low), int(high)


def still_valid(parent: Level, child: Level, parent_problems: set[str] | None = None) -> bool:
    """Whether ``child`` is as valid as ``parent``: it parses as a level of its game (one avatar,
    legal characters, the size limits), is the same size, keeps what the win condition needs
    (never fewer than needed where the parent had enough), and has no playability problem that
    the parent did not have (``parent_problems``: the parent's, if known)."""
    if (child.game, child.height, child.width) != (parent.game, parent.height, parent.width):
        return False
    try:
        Level.parse(str(child), child.game)
    except LevelFormatError:
        return False
    spec = get_game_spec(child.game)
    for need in spec.level_format.win_needs:
        have = sum(child.count(char) for char in need.chars)
        had = sum(parent.count(char) for char in need.chars)
        if have < min(need.count, had):
            return False
    if spec.playability_problems is None:
        return True
    if parent_problems is None:
        parent_problems = set(spec.playability_problems(parent))
    return set(spec.playability_problems(child)) <= parent_problems


def check_editable(level: Level, game: str) -> None:
    """Refuse, in one line, a level that is not one of ``game`` (a ``Level`` built by hand with
    ragged rows, unknown characters, no avatar, no rows at all): the edits assume a valid grid."""
    try:
        Level.parse(str(level), game, source=level.name or f"the hand-built {game} level")
    except (LevelFormatError, TypeError) as error:
        raise ValueError(
            f"the {game} editor was given a level that is not a valid {game} level: {error}"
        ) from None


def apply_edit(
    level: Level, seed: int, kinds: dict[str, EditKind], game: str, bounds: Sequence[Bound] = ()
) -> tuple[str | None, Level]:
    """(the kind applied, the edited level): one edit drawn by ``seed`` that leaves ``level``
    valid and no further outside ``bounds``, redrawn up to ``ATTEMPTS`` times; ``(None, level
    unchanged)`` when none was. The result never carries the parent's name or seed."""
    if level.game != game:
        raise ValueError(
            f"the {game} editor was given a {level.game} level; edit it with its own game's editor"
        )
    check_editable(level, game)
    rng = np.random.default_rng(check_seed(seed))
    names = list(kinds)
    check = get_game_spec(game).playability_problems
    parent_problems = set(check(level)) if check is not None else set()
    for _ in range(ATTEMPTS):
        name = names[int(rng.integers(len(names)))]
        grid = Grid(level)
        if kinds[name](grid, rng):
            edited = grid.level()
            if (
                edited != level
                and keeps_bounds(level, edited, bounds)
                and still_valid(level, edited, parent_problems)
            ):
                return name, edited
    return None, Level(level.game, level.rows)
