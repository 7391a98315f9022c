"""Pixel geometry shared by every game: directions, rectangle overlap, and which grid cells a
10x10 sprite rectangle covers.

All sprites in these games are 10x10 px and positions are integer pixels (RULES.md §1.1), so a
rectangle at (x, y) overlaps at most the 2x2 cells {x//10, (x+9)//10} x {y//10, (y+9)//10}.

GVGAI tests every interaction on pixel rectangles, wherever the sprites are: a level without a
border lets sprites leave its screen, and they keep colliding out there. The games look static
and cell-aligned sprites up by grid cell, which is exact on the screen: a cell holds what is
there. Off an env's own screen (:func:`off_screen`, :func:`screen_cell`) no cell holds anything,
so a rule must test a sprite out there against the sprites it may meet by their rectangles
(:func:`overlaps_any`). No grid of a state holds a sprite off its env's screen, in the padding
that grows a smaller level to its batch's grid (gvgai_pcg/games/base.py) or anywhere else.
"""

from __future__ import annotations

from functools import cache

import torch

from gvgai_pcg.games.lookup import lookup

CELL = 10

# Direction codes follow the Gym's action order for directions: LEFT, RIGHT, DOWN, UP; NONE last.
LEFT, RIGHT, DOWN, UP, NONE = 0, 1, 2, 3, 4
DIRECTION_NAMES = ("LEFT", "RIGHT", "DOWN", "UP", None)
# Unit displacement of each direction code (RULES.md §1.7; y grows downward, NONE stays).
DIRECTION_DX = (-1, 1, 0, 0, 0)
DIRECTION_DY = (0, 0, 1, -1, 0)


@cache
def _zero(dtype: torch.dtype, device: torch.device) -> torch.Tensor:
    return torch.zeros((), dtype=dtype, device=device)


def direction_dx(direction: torch.Tensor, dtype: torch.dtype = torch.int64) -> torch.Tensor:
    """Unit x displacement of direction codes (any shape), as ``dtype``."""
    return lookup(DIRECTION_DX, direction, dtype)


def direction_dy(direction: torch.Tensor, dtype: torch.dtype = torch.int64) -> torch.Tensor:
    """Unit y displacement of direction codes (any shape, y grows downward), as ``dtype``."""
    return lookup(DIRECTION_DY, direction, dtype)


def overlaps(ax: torch.Tensor, ay: torch.Tensor, bx: torch.Tensor, by: torch.Tensor) -> torch.Tensor:
    """Strict overlap of 10x10 rectangles (edge-adjacent cells do not overlap): both distances
    below 10 px, as one test on the larger; broadcasts."""
    return torch.maximum((bx - ax).abs(), (by - ay).abs()) < CELL


def off_screen(
    x: torch.Tensor, y: torch.Tensor, screen_h: torch.Tensor, screen_w: torch.Tensor
) -> torch.Tensor:
    """RULES.md §1.1's "at the edge": whether 10x10 rectangles at ``x, y`` are not entirely inside
    their env's screen of ``screen_h`` x ``screen_w`` px (each env's own, broadcast against x, y)."""
    return (x < 0) | (y < 0) | (x + CELL > screen_w) | (y + CELL > screen_h)


def overlaps_any(
    x: torch.Tensor,
    y: torch.Tensor,
    which: torch.Tensor,
    tx: torch.Tensor,
    ty: torch.Tensor,
    present: torch.Tensor,
) -> torch.Tensor:
    """Whether each sprite at ``x, y`` (``[B]`` or ``[B, E]``) that ``which`` selects overlaps a
    ``present`` sprite of the table ``tx, ty`` (``[B, K]``) of its env, by pixel rectangles; false
    for the sprites not selected.

    This is how rules see sprites off the screen, where no cell holds them. They are few, so they
    are found first (one ``nonzero``) and only they are compared with their env's table. A compiled
    tick cannot take a data-dependent shape, and compares every sprite in one fused loop instead."""
    if torch.compiler.is_compiling():
        batch = which.shape[0]
        sx, sy = x.reshape(batch, -1, 1), y.reshape(batch, -1, 1)
        near = overlaps(sx, sy, tx.unsqueeze(1), ty.unsqueeze(1)) & present.unsqueeze(1)
        return (which.reshape(batch, -1) & near.any(-1)).view(which.shape)
    hit = torch.zeros_like(which)
    flat = hit.view(which.shape[0], -1)
    env, slot = which.reshape(flat.shape).nonzero(as_tuple=True)
    if env.numel():
        sx, sy = x.reshape(flat.shape)[env, slot], y.reshape(flat.shape)[env, slot]
        near = overlaps(sx.unsqueeze(-1), sy.unsqueeze(-1), tx[env], ty[env]) & present[env]
        flat[env, slot] = any_last(near)
    return hit


def overlaps_aligned(ax: torch.Tensor, ay: torch.Tensor, bx: torch.Tensor, by: torch.Tensor) -> torch.Tensor:
    """:func:`overlaps` for rectangles at multiples of 10 px (cell-aligned): they overlap exactly
    when they are at the same place, two comparisons instead of eleven ops; broadcasts."""
    return (ax == bx) & (ay == by)


def any_last(mask: torch.Tensor) -> torch.Tensor:
    """``mask.any(-1)`` as a max over the bytes of the bool mask: the same result, much faster
    than PyTorch's bool ``any`` on the CPU."""
    if mask.shape[-1] == 0:
        return torch.zeros(mask.shape[:-1], dtype=torch.bool, device=mask.device)
    if torch.compiler.is_compiling():
        return mask.any(-1)
    return mask.view(torch.uint8).amax(-1).view(torch.bool)


def count_last(mask: torch.Tensor) -> torch.Tensor:
    """``mask.sum(-1)`` in int32 (a bool sum defaults to int64, which is slower)."""
    return mask.sum(-1, dtype=torch.int32)


# Cell arithmetic: which cell holds a pixel. Integer division is slow on the CPU, so each is a
# multiply and a shift, exact on the range its docstring states (tests/games/test_geometry.py).


def cell_of(position: torch.Tensor) -> torch.Tensor:
    """``floor(position / 10)``: the cell holding a pixel, for any integer tensor, as int64.

    Exact for positions in [-10000, 33000) px, far beyond any screen here.
    """
    return ((position.long() + 10000) * 52429 >> 19) - 1000


def small_cell_of(position: torch.Tensor) -> torch.Tensor:
    """``position // 10`` for 0 <= position < 1029 (positions on a screen of up to 101 cells), in
    the input's dtype: cheaper still than :func:`cell_of`."""
    return (position * 205) >> 11


def centre_cell_of(position: torch.Tensor) -> torch.Tensor:
    """``floor((position + 5) / 10) + 100``: the cell holding the centre of 10x10 sprites at
    ``position``, offset by 100 (so that the cells just off a screen stay positive), in int32.
    Exact for positions in [-1005, 14995), monotonic beyond (the renderer clamps)."""
    return torch.add(_CENTRE_BIAS, position.to(torch.int32), alpha=6554).bitwise_right_shift_(16)


# (p + 1005) * 6554 as one multiply-add: 6554 p + _CENTRE_BIAS.
_CENTRE_BIAS = torch.tensor((CELL // 2 + 1000) * 6554, dtype=torch.int32)


def flat_cell(
    column: torch.Tensor, row: torch.Tensor, height: int, width: int
) -> tuple[torch.Tensor, torch.Tensor]:
    """The flat index (in a grid of ``height`` x ``width`` cells) of cells ``column, row`` (any
    shape), clamped onto the grid, and whether the cell is inside the grid."""
    column_in, row_in = column.clamp(0, width - 1), row.clamp(0, height - 1)
    return row_in * width + column_in, (column_in == column) & (row_in == row)


def screen_cell(
    x: torch.Tensor, y: torch.Tensor, last_x: torch.Tensor, last_y: torch.Tensor, width: int
) -> tuple[torch.Tensor, torch.Tensor]:
    """For cell-aligned rectangles at ``x, y`` (any shape): the flat index (in a grid ``width``
    cells wide) of the cell they cover, clamped onto their env's screen, and whether they are on
    that screen, the only place where the cell holds what they overlap. ``last_x, last_y`` are each
    env's last on-screen position, ``10 * (own width - 1)`` and ``10 * (own height - 1)``,
    broadcast against x, y (at most 1010 px)."""
    if torch.compiler.is_compiling():  # the cached zero below is an eager-only saving
        x_in, y_in = x.clamp(min=0).minimum(last_x), y.clamp(min=0).minimum(last_y)
    else:
        zero = _zero(x.dtype, x.device)
        x_in, y_in = torch.clamp(x, zero, last_x), torch.clamp(y, zero, last_y)
    on = (x_in == x) & (y_in == y)
    return small_cell_of(y_in) * width + small_cell_of(x_in), on


def covered_cells(
    x: torch.Tensor, y: torch.Tensor, height: int, width: int
) -> tuple[torch.Tensor, torch.Tensor]:
    """Flat cell indices ``[..., 4]`` of the (up to four) distinct cells a rectangle overlaps, and a
    validity mask ``[..., 4]`` (false for duplicates and cells outside the grid)."""
    cx0, cy0 = cell_of(x), cell_of(y)
    cx1, cy1 = cell_of(x + CELL - 1), cell_of(y + CELL - 1)
    cxs = torch.stack([cx0, cx1, cx0, cx1], dim=-1)
    cys = torch.stack([cy0, cy0, cy1, cy1], dim=-1)
    split_x, split_y = cx1 != cx0, cy1 != cy0
    distinct = torch.stack([torch.ones_like(split_x), split_x, split_y, split_x & split_y], dim=-1)
    inside = (cxs >= 0) & (cxs < width) & (cys >= 0) & (cys < height)
    index = (cys.clamp(0, height - 1) * width + cxs.clamp(0, width - 1)).long()
    return index, distinct & inside


def aligned_cell(
    x: torch.Tensor, y: torch.Tensor, height: int, width: int
) -> tuple[torch.Tensor, torch.Tensor]:
    """The flat index ``[..., 1]`` of the one cell a cell-aligned rectangle (x, y multiples of 10)
    covers, and whether that cell is inside the grid (``[..., 1]``)."""
    index, inside = flat_cell(cell_of(x), cell_of(y), height, width)
    return index.unsqueeze(-1), inside.unsqueeze(-1)


def row_cells(x: torch.Tensor, y: torch.Tensor, height: int, width: int) -> tuple[torch.Tensor, torch.Tensor]:
    """Flat cell indices ``[..., 2]`` that rectangles at ``x, y`` (any shape) overlap when ``y`` is
    a multiple of 10, so that they cover one row of one or two cells, and a validity mask
    ``[..., 2]`` (false for the second cell of an aligned rectangle and cells off the grid). The
    row is clamped onto the grid: callers keep such rectangles on it."""
    x0 = cell_of(x)
    x1 = cell_of(x + CELL - 1)
    cxs = torch.stack([x0, x1], dim=-1)
    valid = (cxs >= 0) & (cxs < width)
    valid[..., 1] &= x1 != x0
    row = cell_of(y).clamp_(0, height - 1).unsqueeze(-1)
    return row * width + cxs.clamp_(0, width - 1), valid


def gather_cells(grid: torch.Tensor, cells: torch.Tensor, valid: torch.Tensor) -> torch.Tensor:
    """Which of the flat ``cells`` (``[B, ...]``, masked by ``valid`` of the same shape) are set in
    ``grid`` (``[B, H, W]`` bool)."""
    batch = grid.shape[0]
    return torch.gather(grid.reshape(batch, -1), 1, cells.reshape(batch, -1)).view(cells.shape) & valid


def grid_hits(
    grid: torch.Tensor, x: torch.Tensor, y: torch.Tensor, aligned: bool = False
) -> tuple[torch.Tensor, torch.Tensor]:
    """Which covered cells of ``grid`` (``[B, H, W]`` bool) are set under rectangles at ``x, y``
    (``[B]`` or ``[B, K]``): returns (flat cell index ``[..., 4]``, hit mask ``[..., 4]``). With
    ``aligned`` (x, y known to be multiples of 10, so one cell each) both are ``[..., 1]``."""
    _, height, width = grid.shape
    index, valid = (aligned_cell if aligned else covered_cells)(x, y, height, width)
    return index, gather_cells(grid, index, valid)


def grid_count(grid: torch.Tensor, x: torch.Tensor, y: torch.Tensor, aligned: bool = False) -> torch.Tensor:
    """How many set cells of ``grid`` each rectangle overlaps (``[B]`` or ``[B, K]``)."""
    return count_last(grid_hits(grid, x, y, aligned)[1])


def clear_cells_(grid: torch.Tensor, index: torch.Tensor, mask: torch.Tensor) -> None:
    """Unset the cells ``index[mask]`` of ``grid`` (``[B, H, W]`` bool) in place, ``index`` and
    ``mask`` being ``[B, n]`` as from :func:`grid_hits`. Each listed cell is written back with its
    own value unless masked, so a cell may be listed twice in an env only with the same mask (the
    distinct cells of :func:`grid_hits` are). A few gathers, not a pass over the grid."""
    flat = grid.view(grid.shape[0], -1)
    flat.scatter_(1, index, flat.gather(1, index) & ~mask)


def add_at_(table: torch.Tensor, index: torch.Tensor, values: torch.Tensor) -> torch.Tensor:
    """``table.scatter_add_(1, index, values)`` in place, byte tables included, on every device:
    Triton has no atomic add on bytes, so off the CPU a byte table goes through
    :func:`add_bytes_at_`."""
    if table.dtype != torch.uint8 or table.device.type == "cpu":
        return table.scatter_add_(1, index, values)
    return add_bytes_at_(table, index, values)


def add_bytes_at_(table: torch.Tensor, index: torch.Tensor, values: torch.Tensor) -> torch.Tensor:
    """``scatter_add_`` into a byte ``table`` by way of int32 sums, which are then added to the
    bytes, wrapping as a byte add does."""
    sums = torch.zeros(table.shape, dtype=torch.int32, device=table.device)
    return table.add_(sums.scatter_add_(1, index, values.to(torch.int32)).to(torch.uint8))


def clear_listed_cells_(flat: torch.Tensor, index: torch.Tensor, clear: torch.Tensor) -> None:
    """Unset ``flat[b, index[b, k]]`` wherever ``clear[b, k]``, in place (``flat`` a ``[B, H*W]``
    bool grid, ``index`` and ``clear`` ``[B, n]``); a cell listed more than once goes if any of
    its listings says so. On the CPU one ``scatter_reduce_(amin)`` over the grid's bytes does it.
    CUDA has no such kernel for bools, and compiled for CUDA the byte view failed to lower (torch
    2.11), so there the clearings are counted and the cells counted zero kept: two more passes
    over the grid, which cost the CPU a tenth of Boulderdash's compiled step at B = 1,024."""
    if flat.device.type == "cpu":
        flat.view(torch.uint8).scatter_reduce_(1, index, (~clear).view(torch.uint8), "amin")
        return
    clear_counted_cells_(flat, index, clear)


def clear_counted_cells_(flat: torch.Tensor, index: torch.Tensor, clear: torch.Tensor) -> None:
    """:func:`clear_listed_cells_` by counting the clearings of each cell."""
    counts = torch.zeros(flat.shape, dtype=torch.int32, device=flat.device)
    flat.logical_and_(counts.scatter_add_(1, index, clear.to(torch.int32)) == 0)


def write_rows_(
    table: torch.Tensor, index: torch.Tensor, values: torch.Tensor, accumulate: bool = False
) -> torch.Tensor:
    """``table[b, index[b, k]] = values[b, k]`` (``+=`` with ``accumulate``) in place, for
    ``table [B, N]`` and ``index, values [B, K]``; an index repeated in an env gets equal values
    (or is added). Eager by ``scatter_``, the cheapest to dispatch; compiled by ``index_put_``,
    which inductor writes into the table itself, where a ``scatter_`` costs it two copies of the
    whole table (torch 2.13 does not reinplace ``scatter``). The rows come from ``index``: taken
    from ``table``, inductor failed an assertion on the two batch sizes (symbols of their own,
    gvgai_pcg.engine.compiled)."""
    if torch.compiler.is_compiling():
        rows = torch.arange(index.shape[0], device=index.device).unsqueeze(-1)
        return table.index_put_((rows, index), values, accumulate=accumulate)
    if accumulate:
        return table.scatter_add_(1, index, values)
    return table.scatter_(1, index, values)


def observation_shape(game: str, obs: str) -> tuple[int, int, int]:
    """``(C, H, W)`` of one observation of ``game``: one channel per tile type on the level grid
    (``tiles``), or RGB pixels of ``CELL`` x ``CELL`` per cell (``pixels``)."""
    from gvgai_pcg.games.registry import get_game
    from gvgai_pcg.levels import level_format

    rules, fmt = get_game(game), level_format(game)
    if obs == "tiles":
        return (len(rules.tile_types), fmt.height, fmt.width)
    return (3, fmt.height * CELL, fmt.width * CELL)
