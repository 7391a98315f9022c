"""Pieces every generator shares: the uniform stream, framing in `w`, the Level it returns, and
the reachability search its checks use.

The originals draw from JavaScript's ``Math.random()`` one value at a time. ``UniformStream``
plays that role on top of a seeded ``numpy.random.Generator``, fetching draws in blocks because a
numpy call per scalar costs about a microsecond and a level needs a few hundred draws. The
stream is deterministic, so the same seed gives the same level on every machine.
"""

from __future__ import annotations

import numpy as np

from gvgai_pcg.levels.formats import level_format
from gvgai_pcg.levels.level import Level
from gvgai_pcg.levels.padding import centre_rows

_BLOCK = 256


class UniformStream:
    """A callable giving U[0,1) floats from ``rng``, like ``Math.random()`` but seeded."""

    __slots__ = ("_rng", "_it")

    def __init__(self, rng: np.random.Generator) -> None:
        self._rng = rng
        self._it = iter(())

    def __call__(self) -> float:
        try:
            return next(self._it)
        except StopIteration:
            self._it = iter(self._rng.random(_BLOCK).tolist())
            return next(self._it)


def frame(rows: list[str], game: str, pad: str = "w") -> list[str]:
    """Centre ``rows`` in a ``pad`` frame of the game's full size (floor on the left and top)."""
    fmt = level_format(game)
    return centre_rows(rows, fmt.height, fmt.width, pad, game)


def difficulty_tag(difficulty: float) -> str:
    """``d`` as level names write it: plain decimals (no exponent), to 10 places, so that distinct
    difficulties of a sweep get distinct names and a PPCG value such as 0.37000000000000005
    reads 0.37."""
    return np.format_float_positional(difficulty, precision=10, trim="-")


def generated_level(game: str, rows: list[str], difficulty: float, seed: int) -> Level:
    """The Level a generator returns, named ``<game>_d<d>_s<seed>`` and carrying its seed."""
    name = f"{game}_d{difficulty_tag(difficulty)}_s{seed}"
    return Level(game=game, rows=tuple(rows), name=name, seed=seed)


def reachable(level: Level, start: tuple[int, int], blocked: str) -> set[tuple[int, int]]:
    """Cells 4-connected to ``start`` through cells whose character is not in ``blocked``."""
    rows = level.rows
    seen = {start}
    stack = [start]
    while stack:
        r, c = stack.pop()
        for nr, nc in ((r - 1, c), (r + 1, c), (r, c - 1), (r, c + 1)):
            if (
                0 <= nr < len(rows)
                and 0 <= nc < len(rows[0])
                and (nr, nc) not in seen
                and rows[nr][nc] not in blocked
            ):
                seen.add((nr, nc))
                stack.append((nr, nc))
    return seen
