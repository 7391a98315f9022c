"""Observations drawn from layers: the tiles view and the z-buffered pixels."""

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
