"""Growing a level's rows to a larger grid: the one padding of the package, in two placements.

- ``pad_rows``: fill at the bottom and right, so the level keeps its top-left corner. The engine
  pads smaller levels with cells that hold nothing (``gvgai_pcg.games.base.pad_level``); the
  level-distribution analysis pads with walls, as the study padded human Frogs level 4.
- ``centre_rows``: fill around the rows, so they sit in the middle (generators that build a
  smaller interior and frame it at the game's full size).
"""

from __future__ import annotations

from collections.abc import Sequence


def _check_fits(rows: Sequence[str], height: int, width: int, name: str) -> tuple[int, int]:
    own_height, own_width = len(rows), len(rows[0]) if rows else 0
    if own_height > height or own_width > width:
        raise ValueError(f"level {name} is {own_width}x{own_height}, larger than {width}x{height}")
    return own_height, own_width


def pad_rows(rows: Sequence[str], height: int, width: int, fill: str, name: str = "") -> list[str]:
    """``rows`` grown to ``height x width`` with ``fill`` rows at the bottom and columns at the right."""
    own_height, own_width = _check_fits(rows, height, width, name)
    return [row + fill * (width - own_width) for row in rows] + [fill * width] * (height - own_height)


def centre_rows(rows: Sequence[str], height: int, width: int, fill: str, name: str = "") -> list[str]:
    """``rows`` in the middle of a ``height x width`` grid of ``fill`` (one extra cell of fill on the
    right and bottom when the margins are odd)."""
    own_height, own_width = _check_fits(rows, height, width, name)
    left, top = (width - own_width) // 2, (height - own_height) // 2
    sides = fill * left, fill * (width - own_width - left)
    middle = [sides[0] + row + sides[1] for row in rows]
    return [fill * width] * top + middle + [fill * width] * (height - own_height - top)
