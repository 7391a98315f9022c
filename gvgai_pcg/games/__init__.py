"""The games: a registry of ``Game`` rule sets over batched tensor states.

Importing this package registers every built-in game (one module per game below).
"""

from gvgai_pcg.games import boulderdash, frogs, solarfox, zelda  # noqa: F401  (register the games)
from gvgai_pcg.games.base import Game, GridLayer, SpriteArt, SpriteLayer
from gvgai_pcg.games.registry import get_game, register_game, registered_games

__all__ = ["Game", "GridLayer", "SpriteArt", "SpriteLayer", "get_game", "register_game", "registered_games"]
