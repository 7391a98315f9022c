"""Observations drawn from a game's layers: ``tiles`` (one channel per sprite type, a sprite
marked in the cell holding its centre) and ``pixels`` (RGB, 10 px per cell, our own art).

Both are batched tensor ops over all envs; the only Python loop is over a game's handful of
layers (sprite types), never over environments or sprites.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import torch
from tensordict import TensorDict

from gvgai_pcg.engine.buffers import BufferPool
from gvgai_pcg.games.base import Game, GridLayer, SpriteArt, SpriteLayer
from gvgai_pcg.games.geometry import CELL, DOWN, LEFT, RIGHT, UP, centre_cell_of
from gvgai_pcg.levels import Level


def _shape_mask(shape: str) -> torch.Tensor:
    """``[10, 10]`` bool footprint of a shape name."""
    yy, xx = torch.meshgrid(torch.arange(CELL), torch.arange(CELL), indexing="ij")
    cx, cy = xx - 4.5, yy - 4.5
    shapes = {
        "square": torch.ones(CELL, CELL, dtype=torch.bool),
        "circle": cx**2 + cy**2 <= 16.5,
        "diamond": cx.abs() + cy.abs() <= 5.0,
        "small": (xx >= 1) & (xx < 8) & (yy >= 1) & (yy < 8),
        "frame": (xx == 0) | (xx == 9) | (yy == 0) | (yy == 9) | ((xx - yy).abs() <= 0),
        "cross": (cx.abs() <= 1) | (cy.abs() <= 1),
        "bar": (yy >= 3) & (yy < 7),
        "dot": cx**2 + cy**2 <= 6.5,
    }
    if shape not in shapes:
        raise ValueError(f"unknown art shape {shape!r}; valid shapes are: {', '.join(shapes)}")
    return shapes[shape]


def _facing_marker(direction: int) -> torch.Tensor:
    """``[10, 10]`` bool triangle pointing along ``direction`` (RULES.md §1.9, simplified)."""
    yy, xx = torch.meshgrid(torch.arange(CELL), torch.arange(CELL), indexing="ij")
    along = {RIGHT: xx, LEFT: 9 - xx, DOWN: yy, UP: 9 - yy}[direction]
    across = {RIGHT: yy, LEFT: yy, DOWN: xx, UP: xx}[direction]
    return (along >= 6) & ((across - 4.5).abs() <= (9 - along) + 0.5)


def sprite_images(art: SpriteArt) -> torch.Tensor:
    """``[V, 4, 10, 10]`` uint8 RGBA images of a type: one, or one per facing (LEFT, RIGHT, DOWN, UP)."""
    mask = _shape_mask(art.shape)
    color = torch.tensor(art.color, dtype=torch.uint8).view(3, 1, 1)
    base = torch.cat([color.expand(3, CELL, CELL), (mask * 255).to(torch.uint8).unsqueeze(0)])
    if not art.oriented:
        return base.unsqueeze(0)
    marker_color = torch.tensor((art.color[0], 255 - art.color[1], art.color[2]), dtype=torch.uint8).view(
        3, 1, 1
    )
    variants = []
    for direction in (LEFT, RIGHT, DOWN, UP):
        marker = _facing_marker(direction)
        image = base.clone()
        image[:3] = torch.where(marker, marker_color, image[:3])
        image[3] = torch.where(marker, torch.tensor(255, dtype=torch.uint8), image[3])
        variants.append(image)
    return torch.stack(variants)


@cache
def _images(game_name: str, type_name: str, device: str) -> torch.Tensor:
    from gvgai_pcg.games.registry import get_game

    return sprite_images(get_game(game_name).art[type_name]).to(device)


def render_tiles(game: Game, state: TensorDict, pool: BufferPool | None = None) -> torch.Tensor:
    """``[B, C, H, W]`` uint8 (contiguous), channel c = ``game.tile_types[c]``; a sprite is marked
    in the cell that holds its centre, if that cell is on its env's own screen (a sprite that has
    left a smaller level's screen is not shown in the padding around it, as GVGAI shows nothing
    beyond a screen).

    The tiles are a view of a flat buffer with one spare byte after them that takes the marks of
    every sprite that is absent or off the grid, so every sprite layer is one plain scatter of
    ones and the result stays contiguous (its clones and row copies run at memcpy speed). The
    buffer comes from ``pool`` if one is given.
    """
    layers = game.layers(state)
    grid = next(layer.cells for layer in layers if isinstance(layer, GridLayer))
    batch, height, width = grid.shape
    cells, channels = height * width, len(game.tile_types)
    channel_of = {name: c for c, name in enumerate(game.tile_types)}
    grids: dict[int, list[torch.Tensor]] = {}
    for layer in layers:
        if isinstance(layer, GridLayer) and layer.name in channel_of:
            grids.setdefault(channel_of[layer.name], []).append(layer.cells.reshape(batch, cells))
    size = channels * cells
    spare = batch * size
    if pool is None:
        flat = torch.empty(spare + 1, dtype=torch.uint8, device=grid.device)
    else:
        flat = pool.empty(spare + 1, torch.uint8, grid.device)
    tiles = flat[:spare].view(batch, channels, cells)
    _zero_sprite_channels(tiles, set(grids))
    for channel, drawn in grids.items():
        tiles[:, channel].copy_(drawn[0])  # bool to uint8 (faster than from a uint8 view)
        for more in drawn[1:]:
            tiles[:, channel].bitwise_or_(more.view(torch.uint8))
    # Sprites are marked by a scatter into the flat buffer (cheaper than one along dim 1); each
    # index carries its env's row start. int32 like the cell arithmetic (a mixed-dtype op would
    # first copy its int32 side to int64).
    index_type = torch.int32 if spare < 2**31 else torch.int64
    rows = torch.arange(batch, device=grid.device, dtype=index_type).unsqueeze(-1) * size
    sprites = [
        (channel_of[layer.name], layer)
        for layer in layers
        if isinstance(layer, SpriteLayer) and layer.name in channel_of
    ]
    ends = _screen_ends(state)
    for group in _sprite_groups(sprites):
        index = _sprite_index(group, rows, height, width, spare, ends)
        flat.scatter_(0, index, _ones(index.numel(), tiles.device))
    return tiles.view(batch, channels, height, width)


def render_tiles_traced(game: Game, state: TensorDict) -> torch.Tensor:
    """:func:`render_tiles` in the form a compiled graph takes well: the grid channels built by
    one stack, every sprite marked by one max-scatter (an absent sprite writes a 0), no buffer pool
    and no cached helper tensors. Compiled, the in-place writes into slices of one buffer that
    ``render_tiles`` makes each became a copy of the whole buffer. Eagerly this form is slower."""
    layers = game.layers(state)
    grid = next(layer.cells for layer in layers if isinstance(layer, GridLayer))
    batch, height, width = grid.shape
    cells, channels = height * width, len(game.tile_types)
    channel_of = {name: c for c, name in enumerate(game.tile_types)}
    planes: list[torch.Tensor | None] = [None] * channels
    for layer in layers:
        if isinstance(layer, GridLayer) and layer.name in channel_of:
            c, plane = channel_of[layer.name], layer.cells.reshape(batch, cells)
            planes[c] = plane if planes[c] is None else planes[c] | plane
    blank = torch.zeros(batch, cells, dtype=torch.uint8, device=grid.device)
    tiles = torch.stack([blank if plane is None else plane.to(torch.uint8) for plane in planes], dim=1)
    size = channels * cells
    rows = torch.arange(batch, device=grid.device, dtype=torch.int64).unsqueeze(-1) * size
    index, shown, ends = [], [], _screen_ends(state)
    for layer in layers:
        if isinstance(layer, SpriteLayer) and layer.name in channel_of:
            cell, visible = _sprite_cells([(channel_of[layer.name], layer)], rows, height, width, ends)
            index.append(cell.mul_(visible).view(-1))  # an absent sprite marks cell 0 with a 0,
            shown.append(visible.view(-1))  # which the max leaves as it was
    if not index:
        return tiles.view(batch, channels, height, width)
    marks, values = torch.cat(index), torch.cat(shown).to(torch.uint8)
    flat = tiles.view(-1).scatter_reduce(0, marks, values, "amax")
    return flat.view(batch, channels, height, width)


SMALL_LAYER = 1 << 15  # envs x slots up to which sprite layers are marked together


def _sprite_groups(sprites: list[tuple[int, SpriteLayer]]) -> list[list[tuple[int, SpriteLayer]]]:
    """Sprite layers to mark in one pass. Small layers are marked together (those with lane rows
    apart from the others), since their ops cost little but dispatch; a large layer is marked
    alone, as joining it to others would copy more than the ops it saves."""
    alone, together = [], {}
    for channel, layer in sprites:
        if layer.x.numel() > SMALL_LAYER:
            alone.append([(channel, layer)])
        else:
            together.setdefault(layer.row is None, []).append((channel, layer))
    return alone + list(together.values())


def _screen_ends(state: TensorDict) -> tuple[torch.Tensor, torch.Tensor]:
    """``[B, 1]`` int32 each: the first row and column (offset by 100, as ``centre_cell_of``'s)
    beyond each env's own screen, which ends there in a level smaller than the batch's grid."""
    return tuple((state.get(key) + 100).to(torch.int32).unsqueeze(-1) for key in ("height", "width"))


def _sprite_index(
    group: list[tuple[int, SpriteLayer]],
    rows: torch.Tensor,
    height: int,
    width: int,
    spare: int,
    ends: tuple[torch.Tensor, torch.Tensor],
) -> torch.Tensor:
    """Flat int64 buffer index of every slot of the ``group`` (layers that all have lane rows or
    none have): the cell of its centre in its channel, or ``spare`` if absent or off its env's
    screen (``ends``: :func:`_screen_ends`)."""
    cell, shown = _sprite_cells(group, rows - spare, height, width, ends)
    # spare + (cell - spare) * shown: a select by arithmetic, as torch.where (and masked_fill) on
    # the CPU cost many times an add here.
    return cell.mul_(shown).view(-1).long().add_(spare)


def _sprite_cells(
    group: list[tuple[int, SpriteLayer]],
    rows: torch.Tensor,
    height: int,
    width: int,
    ends: tuple[torch.Tensor, torch.Tensor],
) -> tuple[torch.Tensor, torch.Tensor]:
    """``rows`` plus the cell of each slot's centre in its channel, and whether it is shown
    (present and on its env's own screen, which ``ends`` closes: :func:`_screen_ends`), for the
    ``group`` (layers that all have lane rows or none have; a lane row is one of its level's)."""
    layers = [layer for _, layer in group]
    lanes = layers[0].row is not None
    # Each layer's channel start, less the offset of 100 of centre_cell_of (in rows too unless given).
    starts = [channel * height * width - 100 - (0 if lanes else 100 * width) for channel, _ in group]
    if len(group) == 1:
        (layer,) = layers
        x, y, present, row, first = layer.x, layer.y, layer.present, layer.row, rows + starts[0]
    else:
        x = torch.cat([layer.x for layer in layers], dim=1)
        y = None if lanes else torch.cat([layer.y for layer in layers], dim=1)
        row = torch.cat([layer.row for layer in layers], dim=1) if lanes else None
        present = torch.cat([layer.present for layer in layers], dim=1)
        counts = tuple(layer.x.shape[1] for layer in layers)
        first = rows + _slot_starts(tuple(starts), counts, str(rows.device), rows.dtype)
    column = centre_cell_of(x)
    shown = present & (column >= 100) & (column < ends[1])
    if row is None:
        row = centre_cell_of(y)
        shown &= (row >= 100) & (row < ends[0])
    return torch.add(first, row, alpha=width).add_(column), shown


@cache
def _slot_starts(
    starts: tuple[int, ...], counts: tuple[int, ...], device: str, dtype: torch.dtype
) -> torch.Tensor:
    """``[K]``: each slot's layer start, for layers of ``counts`` slots marked together."""
    return torch.tensor(starts, dtype=dtype, device=device).repeat_interleave(
        torch.tensor(counts, device=device)
    )


def _zero_sprite_channels(tiles: torch.Tensor, grid_channels: set[int]) -> None:
    """Zero the channels no grid is copied into: one fill per run of consecutive channels (games
    list their grid types first, so usually a single fill over part of each env's row)."""
    start = None
    for channel in range(tiles.shape[1] + 1):
        blank = channel < tiles.shape[1] and channel not in grid_channels
        if blank and start is None:
            start = channel
        elif not blank and start is not None:
            tiles[:, start:channel].zero_()
            start = None


_ONES: dict[torch.device, torch.Tensor] = {}


def _ones(count: int, device: torch.device) -> torch.Tensor:
    """``count`` uint8 ones (a slice of one kept buffer): a 1-D ``scatter_`` from a real tensor is
    faster than ``put_`` or a scatter of a scalar."""
    ones = _ONES.get(device)
    if ones is None or ones.numel() < count:
        ones = _ONES[device] = torch.ones(max(count, 1 << 16), dtype=torch.uint8, device=device)
    return ones[:count]


def _depth_images(game: Game, type_name: str, depth: int, device: torch.device) -> torch.Tensor:
    """``[V, 10, 10]`` int32 pixels ``depth << 24 | B << 16 | G << 8 | R``; transparent pixels are 0."""
    rgba = _images(game.name, type_name, str(device)).to(torch.int32)  # [V, 4, 10, 10]
    packed = (depth << 24) | rgba[:, 0] | (rgba[:, 1] << 8) | (rgba[:, 2] << 16)
    return torch.where(rgba[:, 3] > 0, packed, 0)


@cache
def _grid_atlas(game_name: str, grid_layers: tuple[tuple[str, int], ...], device: str) -> torch.Tensor:
    """``[2^n, 100]`` depth-packed pictures of every combination of the n grid layers, composited
    in drawing order (bit i set = layer i present in the cell)."""
    from gvgai_pcg.games.registry import get_game

    game = get_game(game_name)
    images = [
        _depth_images(game, name, depth, torch.device(device))[0].view(-1) for name, depth in grid_layers
    ]
    atlas = torch.zeros(1 << len(images), CELL * CELL, dtype=torch.int32, device=device)
    for combo in range(1 << len(images)):
        for i, image in enumerate(images):
            if combo >> i & 1:
                atlas[combo] = torch.where(image != 0, image, atlas[combo])
    return atlas


def _draw_grids(layers: list, game: Game, batch: int, height: int, width: int) -> torch.Tensor:
    """``[B, 10H * 10W]`` depth-packed canvas of all grid layers, drawn in one gather: each cell's
    set of grid sprites indexes a precomposited picture."""
    grids = [(depth, layer) for depth, layer in enumerate(layers, start=1) if isinstance(layer, GridLayer)]
    device = grids[0][1].cells.device
    combo = torch.zeros(batch, height, width, dtype=torch.int64, device=device)
    for bit, (_, layer) in enumerate(grids):
        combo |= layer.cells.to(torch.int64) << bit
    key = tuple((layer.name, depth) for depth, layer in grids)
    pixels = _grid_atlas(game.name, key, str(device)).index_select(0, combo.view(-1))
    return pixels.view(batch, height, width, CELL, CELL).transpose(2, 3).reshape(batch, -1)


def _draw_sprites(
    canvas: torch.Tensor, layer: SpriteLayer, depth: int, game: Game, width: int, screens: torch.Tensor
) -> None:
    """Scatter a sprite layer into the depth-packed canvas: a pixel keeps the highest depth, so the
    result is the drawing order's whatever order the scatter runs in. A sprite is cut at its env's
    own screen (``screens``: ``[B, 2]`` its height and width in pixels), so a level smaller than
    the batch's grid shows nothing in the padding around it.

    Only present sprites are drawn: their slots are gathered first, as entity tables are mostly
    empty (a quarter of Frogs' log slots hold a log), and every drawn sprite costs 100 pixels.
    """
    row_pixels, device = canvas.shape[1], canvas.device
    pw = width * CELL
    env, slot = layer.present.nonzero(as_tuple=True)
    if env.numel() == 0:
        return
    images = _depth_images(game, layer.name, depth, device)
    if layer.variant is None:
        image = images[0].expand(env.numel(), CELL, CELL)
    else:
        image = images[layer.variant[env, slot].clamp(0, images.shape[0] - 1)]  # [N, 10, 10]
    offsets = torch.arange(CELL, device=device, dtype=torch.int32)
    px = layer.x[env, slot].to(torch.int32).view(-1, 1, 1) + offsets.view(1, 1, CELL)  # [N, 1, 10]
    py = layer.y[env, slot].to(torch.int32).view(-1, 1, 1) + offsets.view(1, CELL, 1)  # [N, 10, 1]
    screen = screens.index_select(0, env)
    ph, own_pw = screen[:, :1].view(-1, 1, 1), screen[:, 1:].view(-1, 1, 1)
    inside = (px >= 0) & (px < own_pw) & (py >= 0) & (py < ph)  # [N, 10, 10]
    # Pixels off the frame go to their env's first pixel with the value 0, which amax ignores.
    local = (py * pw + px) * inside
    index = (env.view(-1, 1, 1) * row_pixels + local).view(-1)
    canvas.view(-1).scatter_reduce_(0, index, (image * inside).reshape(-1), reduce="amax")


def render_pixels(game: Game, state: TensorDict) -> torch.Tensor:
    """``[B, 3, 10H, 10W]`` uint8 RGB frame; uncovered pixels are black (GVGAI has no background).

    A z-buffer keeps the drawing order: every pixel is an int ``depth << 24 | RGB`` where depth is
    the layer's place in the drawing order. The grid layers are drawn in one gather (each cell's
    combination of grid sprites picks a precomposited picture), then each sprite layer is
    scattered with ``amax``, so a sprite shows exactly where no later-drawn layer covers it.
    """
    layers = game.layers(state)
    grid = next(layer.cells for layer in layers if isinstance(layer, GridLayer))
    batch, height, width = grid.shape
    canvas = _draw_grids(layers, game, batch, height, width)
    screens = (CELL * torch.stack([state.get("height"), state.get("width")], dim=-1)).to(torch.int32)
    for depth, layer in enumerate(layers, start=1):
        if isinstance(layer, SpriteLayer):
            _draw_sprites(canvas, layer, depth, game, width, screens)
    rgb = canvas.view(torch.uint8).view(batch, height * CELL, width * CELL, 4)[..., :3]
    return rgb.permute(0, 3, 1, 2).contiguous()


def level_pictures(levels: list[Level]) -> np.ndarray:
    """``[N, 10H, 10W, 3]`` uint8 RGB pictures of levels of one game as they start (before the
    reset tick), in the batch's largest grid like the env shows them."""
    from gvgai_pcg.games.registry import get_game

    game = get_game(levels[0].game)
    state = game.compile(levels, torch.zeros(len(levels), dtype=torch.int64), torch.device("cpu"))
    return render_pixels(game, state).permute(0, 2, 3, 1).numpy()


def ascii_frame(game: Game, state: TensorDict, index: int = 0) -> str:
    """Env ``index`` as text, one character per cell: the last-drawn type's level char, else '.'.

    Meant for debugging; the characters come from the first letter of each tile type.
    """
    tiles = render_tiles(game, state)[index]
    _, height, width = tiles.shape
    rows = [["." for _ in range(width)] for _ in range(height)]
    for channel, name in enumerate(game.tile_types):
        symbol = name[0].upper() if name in ("avatar", "nokey", "withkey") else name[0]
        for r, c in (tiles[channel] > 0).nonzero().tolist():
            rows[r][c] = "A" if name in ("avatar", "nokey", "withkey") else symbol
    return "\n".join("".join(row) for row in rows)
