"""Observations drawn from layers: the tiles view and the z-buffered pixels."""

import pytest
import torch

from gvgai_pcg.games import get_game
from gvgai_pcg.games.render import render_pixels, render_tiles, sprite_images
from gvgai_pcg.levels import Level


def compiled(game: str, rows: tuple[str, ...]):
    g = get_game(game)
    state = g.compile([Level(game, rows)], torch.tensor([0]), torch.device("cpu"))
    g.tick(state, torch.tensor([0]))
    return g, state


def art(game, name, variant=0):
    return sprite_images(get_game(game).art[name])[variant]  # [4, 10, 10]


def test_stacked_grid_sprites_show_the_lower_one_through_transparent_pixels():
    game, state = compiled("zelda", ("wwwww", "wA+gw", "wwwww"))
    frame = render_pixels(game, state)[0]
    key, floor = art("zelda", "key"), art("zelda", "floor")
    cell = frame[:, 10:20, 20:30]
    expected = torch.where(key[3] > 0, key[:3], floor[:3])
    assert torch.equal(cell, expected)


def test_a_sprite_under_a_later_grid_layer_is_hidden():
    # Solarfox draws walls after the enemies: an enemy in a wall column is not visible.
    game, state = compiled("solarfox", ("w2.w", "w+Aw", "w..w"))
    state.get("enemies").set("col", torch.zeros_like(state.get("enemies").get("col")))
    frame = render_pixels(game, state)[0]
    wall = art("solarfox", "wall")
    assert torch.equal(frame[:, 0:10, 0:10], torch.where(wall[3] > 0, wall[:3], 0))
    assert render_tiles(game, state)[0, game.tile_types.index("top"), 0, 0] == 1  # still in the tiles


def test_an_oriented_avatar_is_drawn_with_its_facing():
    game, state = compiled("zelda", ("wwwww", "w.A.w", "wwwww"))
    left_facing = art("zelda", "nokey", variant=0)
    game.tick(state, torch.tensor([game.actions.index("LEFT")]))  # turn in place
    frame = render_pixels(game, state)[0]
    floor = art("zelda", "floor")
    assert torch.equal(frame[:, 10:20, 20:30], torch.where(left_facing[3] > 0, left_facing[:3], floor[:3]))


def test_tiles_mark_the_cell_holding_a_sprite_centre():
    game, state = compiled("solarfox", ("w....w", "w+A++w", "w++++w", "w....w"))
    for _ in range(5):  # after the reset tick the ship flies right 1 px per tick: x = 25
        game.tick(state, torch.tensor([0]))
    tiles = render_tiles(game, state)[0, game.tile_types.index("avatar")]
    assert state.get("avatar").get("x").item() == 25
    assert tiles.nonzero().tolist() == [[1, 3]]  # centre at x = 30: column 3


def reference_tiles(game, state, index: int) -> torch.Tensor:
    """Env ``index``'s tiles marked one sprite at a time in Python: the meaning render_tiles must keep."""
    layers = game.layers(state)
    height, width = next(layer.cells for layer in layers if hasattr(layer, "cells")).shape[1:]
    tiles = torch.zeros(len(game.tile_types), height, width, dtype=torch.uint8)
    for layer in layers:
        if layer.name not in game.tile_types:
            continue
        channel = game.tile_types.index(layer.name)
        if hasattr(layer, "cells"):
            tiles[channel] |= layer.cells[index].to(torch.uint8)
            continue
        for x, y, present in zip(layer.x[index], layer.y[index], layer.present[index], strict=True):
            column, row = (int(x) + 5) // 10, (int(y) + 5) // 10
            if present and 0 <= column < width and 0 <= row < height:
                tiles[channel, row, column] = 1
    return tiles


@pytest.mark.parametrize("small_layer", [0, 1 << 15], ids=["layers-alone", "small-layers-together"])
@pytest.mark.parametrize("name", ["zelda", "solarfox", "frogs", "boulderdash"])
def test_tiles_equal_marking_each_sprite_on_its_own(name, small_layer, monkeypatch):
    from gvgai_pcg.games import render
    from gvgai_pcg.levels import human_levels

    monkeypatch.setattr(render, "SMALL_LAYER", small_layer)

    game = get_game(name)
    levels = [human_levels(name)[i % 5] for i in range(10)]
    state = game.compile(levels, torch.arange(10), torch.device("cpu"))
    generator = torch.Generator().manual_seed(1)
    for tick in range(120):
        game.tick(state, torch.randint(0, game.num_actions, (10,), generator=generator))
        if tick % 20 == 19:
            tiles = render_tiles(game, state)
            assert tiles.is_contiguous()  # clones and row copies of observations stay memcpy-fast
            for index in range(10):
                assert torch.equal(tiles[index], reference_tiles(game, state, index))


def test_tiles_leave_sprites_off_the_grid_unmarked():
    game, state = compiled("solarfox", ("w....w", "w+A++w", "w++++w", "w....w"))
    avatar = state.get("avatar")
    for x, y in ((-6, 10), (55, 10), (10, -6), (10, 35), (-500, -500), (9000, 10)):
        avatar.update({"x": torch.tensor([x]), "y": torch.tensor([y])})
        assert render_tiles(game, state)[0, game.tile_types.index("avatar")].sum() == 0, (x, y)
    avatar.update({"x": torch.tensor([-5]), "y": torch.tensor([34])})  # centre (0, 39): cell (0, 3)
    assert render_tiles(game, state)[0, game.tile_types.index("avatar")].nonzero().tolist() == [[3, 0]]


def test_a_layer_that_gives_its_rows_renders_as_one_that_does_not(monkeypatch):
    from dataclasses import replace

    from gvgai_pcg.games.base import SpriteLayer
    from gvgai_pcg.levels import human_levels

    game = get_game("zelda")
    state = game.compile(list(human_levels("zelda")), torch.arange(5), torch.device("cpu"))
    generator = torch.Generator().manual_seed(0)
    for _ in range(30):
        game.tick(state, torch.randint(0, game.num_actions, (5,), generator=generator))
    plain = render_tiles(game, state)
    layers = game.layers(state)
    with_rows = [
        replace(layer, row=(layer.y // 10).to(torch.int32)) if isinstance(layer, SpriteLayer) else layer
        for layer in layers
    ]
    monkeypatch.setattr(game, "layers", lambda _: with_rows)
    assert torch.equal(render_tiles(game, state), plain)


def reference_pixels(game, state, index: int) -> torch.Tensor:
    """Env ``index``'s frame painted one sprite at a time in drawing order, in Python."""
    layers = game.layers(state)
    height, width = next(layer.cells for layer in layers if hasattr(layer, "cells")).shape[1:]
    frame = torch.zeros(3, height * 10, width * 10, dtype=torch.uint8)

    def paste(image: torch.Tensor, x: int, y: int) -> None:  # the part inside the frame
        x0, y0, x1, y1 = max(x, 0), max(y, 0), min(x + 10, width * 10), min(y + 10, height * 10)
        if x0 < x1 and y0 < y1:
            part = image[:, y0 - y : y1 - y, x0 - x : x1 - x]
            shown = part[3] > 0
            frame[:, y0:y1, x0:x1][:, shown] = part[:3][:, shown]

    for layer in layers:
        images = sprite_images(game.art[layer.name])
        if hasattr(layer, "cells"):
            for row, column in layer.cells[index].nonzero().tolist():
                paste(images[0], 10 * column, 10 * row)
            continue
        variants = layer.variant[index] if layer.variant is not None else torch.zeros_like(layer.x[index])
        for x, y, present, variant in zip(
            layer.x[index], layer.y[index], layer.present[index], variants, strict=True
        ):
            if present:
                paste(images[min(int(variant), len(images) - 1)], int(x), int(y))
    return frame


@pytest.mark.parametrize("name", ["zelda", "solarfox", "frogs", "boulderdash"])
def test_pixels_equal_painting_each_sprite_on_its_own(name):
    from gvgai_pcg.games.base import pad_level
    from gvgai_pcg.levels import human_levels

    game = get_game(name)
    levels = human_levels(name)
    height, width = max(lv.height for lv in levels), max(lv.width for lv in levels)
    levels = [pad_level(levels[i % 5], height, width) for i in range(3)]
    state = game.compile(levels, torch.arange(3), torch.device("cpu"))
    generator = torch.Generator().manual_seed(4)
    for _ in range(25):
        game.tick(state, torch.randint(0, game.num_actions, (3,), generator=generator))
    frames = render_pixels(game, state)
    for index in range(3):
        assert torch.equal(frames[index], reference_pixels(game, state, index))


@pytest.mark.parametrize("fused", [False, True])
def test_a_sprite_that_leaves_a_smaller_levels_screen_is_not_shown_in_its_padding(fused):
    # A Boulderdash level without walls lets the avatar walk off its screen; batched with a larger
    # level, the cells beyond its screen are padding, where GVGAI shows nothing (found by the
    # property test over valid levels: the env's tiles showed it there, the engine alone did not).
    from gvgai_pcg.games.render import render_tiles_traced
    from gvgai_pcg.levels import human_level

    game = get_game("boulderdash")
    state = game.compile(
        [Level("boulderdash", ("A-",)), human_level("boulderdash", 0)], torch.arange(2), torch.device("cpu")
    )
    right = game.actions.index("RIGHT")
    before = render_pixels(game, state)[0]
    while state.get(("avatar", "x"))[0] < 40:  # two cells beyond its two
        game.tick(state, torch.tensor([right, 0]))
    tiles = (render_tiles_traced if fused else render_tiles)(game, state)[0]
    assert not tiles[:, :, 2:].any() and not tiles[:, 1:].any()
    frame = render_pixels(game, state)[0]  # the padding drawn as before the avatar came
    assert torch.equal(frame[:, :, 20:], before[:, :, 20:]) and torch.equal(frame[:, 10:], before[:, 10:])
