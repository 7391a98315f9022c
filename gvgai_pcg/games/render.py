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

from gvgai_pcg.games.base import Game, GridLayer, SpriteArt, SpriteLayer
from gvgai_pcg.games.geometry import CELL, DOWN, LEFT, RIGHT, UP
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


def centre_cell(position: torch.Tensor) -> torch.Tensor:
    """The cell holding a sprite's centre along one axis, ``floor((p + 5) / 10)``, as int32.

    Exact for centres in [0, 1029) px (every screen here is smaller); a centre left of or above
    the screen gives a negative cell. A multiply and a shift, because integer division is slow on
    the CPU.
    """
    return ((position.to(torch.int32) + CELL // 2) * 205) >> 11


def render_tiles(game: Game, state: TensorDict) -> torch.Tensor:
    """``[B, C, H, W]`` uint8, channel c = ``game.tile_types[c]``."""
    layers = game.layers(state)
    grid = next(layer.cells for layer in layers if isinstance(layer, GridLayer))
    batch, height, width = grid.shape
    channel_of = {name: c for c, name in enumerate(game.tile_types)}
    tiles = torch.zeros(batch, len(game.tile_types), height * width, dtype=torch.uint8, device=grid.device)
    for layer in layers:
        channel = channel_of.get(layer.name)
        if channel is None:
            continue
        plane = tiles[:, channel]
        if isinstance(layer, GridLayer):
            plane |= layer.cells.reshape(batch, -1).to(torch.uint8)
            continue
        cx, cy = centre_cell(layer.x), centre_cell(layer.y)
        inside = layer.present & (cx >= 0) & (cx < width) & (cy >= 0) & (cy < height)
        index = torch.where(inside, cy * width + cx, 0).reshape(batch, -1).long()
        plane.scatter_reduce_(1, index, inside.reshape(batch, -1).to(torch.uint8), reduce="amax")
    return tiles.view(batch, len(game.tile_types), height, width)


def _packed_images(game: Game, type_name: str, device: torch.device) -> torch.Tensor:
    """``[V, 10, 10]`` int32: each RGBA pixel packed in one int (R in the low byte), 0 = transparent."""
    rgba = _images(game.name, type_name, str(device)).to(torch.int32)  # [V, 4, 10, 10]
    packed = rgba[:, 0] | (rgba[:, 1] << 8) | (rgba[:, 2] << 16) | (rgba[:, 3] << 24)
    return torch.where(rgba[:, 3] > 0, packed, 0)


def _composite_grid_run(canvas: torch.Tensor, run: list[GridLayer], game: Game, first: bool) -> None:
    """Draw consecutive grid layers in one pass: pick each cell's top image, expand it to pixels."""
    batch, height, width = run[0].cells.shape
    device = canvas.device
    atlas = torch.cat(
        [torch.zeros(1, CELL, CELL, dtype=torch.int32, device=device)]
        + [_packed_images(game, layer.name, device)[:1] for layer in run]
    )  # [1 + len(run), 10, 10], index 0 = nothing
    top = torch.zeros(batch, height, width, dtype=torch.int64, device=device)
    for i, layer in enumerate(run, start=1):
        top = torch.where(layer.cells, i, top)
    pixels = atlas.view(len(run) + 1, CELL * CELL).index_select(0, top.view(-1))
    pixels = (
        pixels.view(batch, height, width, CELL, CELL).transpose(2, 3).reshape(batch, -1)
    )  # [B, 10H * 10W]
    if first:
        canvas[:, :-1] = pixels
    else:
        canvas[:, :-1] = torch.where(pixels != 0, pixels, canvas[:, :-1])


def _draw_sprites(canvas: torch.Tensor, layer: SpriteLayer, game: Game, height: int, width: int) -> None:
    batch, k = layer.x.shape
    device = canvas.device
    ph, pw = height * CELL, width * CELL
    images = _packed_images(game, layer.name, device)
    offsets = torch.arange(CELL, device=device)
    px = layer.x.view(batch, k, 1, 1) + offsets.view(1, 1, 1, CELL)  # [B, K, 1, 10]
    py = layer.y.view(batch, k, 1, 1) + offsets.view(1, 1, CELL, 1)  # [B, K, 10, 1]
    variant = layer.variant if layer.variant is not None else torch.zeros_like(layer.x)
    image = images[variant.clamp(0, images.shape[0] - 1)]  # [B, K, 10, 10]
    visible = (
        layer.present.view(batch, k, 1, 1) & (px >= 0) & (px < pw) & (py >= 0) & (py < ph) & (image != 0)
    )
    index = torch.where(visible, py * pw + px, ph * pw).reshape(batch, -1)
    canvas.scatter_(1, index, image.reshape(batch, -1))


def render_pixels(game: Game, state: TensorDict) -> torch.Tensor:
    """``[B, 3, 10H, 10W]`` uint8 RGB frame; uncovered pixels are black (GVGAI has no background).

    Layers are drawn in the game's drawing order on a canvas of packed RGBA ints: runs of
    consecutive grid layers are composited in one pass, sprites are scattered at their exact
    pixel positions.
    """
    layers = game.layers(state)
    grid = next(layer.cells for layer in layers if isinstance(layer, GridLayer))
    batch, height, width = grid.shape
    ph, pw = height * CELL, width * CELL
    canvas = torch.zeros(batch, ph * pw + 1, dtype=torch.int32, device=grid.device)  # last pixel: a dump
    run: list[GridLayer] = []
    drawn_any = False
    for layer in [*layers, None]:
        if isinstance(layer, GridLayer):
            run.append(layer)
            continue
        if run:
            _composite_grid_run(canvas, run, game, first=not drawn_any)
            run, drawn_any = [], True
        if layer is not None:
            _draw_sprites(canvas, layer, game, height, width)
            drawn_any = True
    rgba = canvas[:, :-1].contiguous().view(torch.uint8).view(batch, ph, pw, 4)
    return rgba[..., :3].permute(0, 3, 1, 2).contiguous()


def level_pictures(levels: list[Level]) -> np.ndarray:
    """``[N, 10H, 10W, 3]`` uint8 RGB pictures of levels of one game as they start (before the
    reset tick), padded to the batch's largest grid like the env pads them."""
    from gvgai_pcg.games.base import pad_level
    from gvgai_pcg.games.registry import get_game

    game = get_game(levels[0].game)
    height, width = max(lv.height for lv in levels), max(lv.width for lv in levels)
    padded = [pad_level(level, height, width, game.pad_char) for level in levels]
    state = game.compile(padded, torch.zeros(len(padded), dtype=torch.int64), torch.device("cpu"))
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
