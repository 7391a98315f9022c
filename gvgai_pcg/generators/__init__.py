"""Constructive level generators (Justesen et al. 2018, GENERATORS.md §1), one module per game.

``generate_level(game, difficulty, seed)`` is the entry point; importing this package registers
the four games' generators, and other packages can add theirs through the
``gvgai_pcg.generators`` entry-point group.
"""

from gvgai_pcg.generators import boulderdash, frogs, solarfox, zelda  # noqa: F401  (they register)
from gvgai_pcg.generators.registry import (
    generate_level,
    get_generator,
    register_generator,
    registered_generators,
)

__all__ = ["generate_level", "get_generator", "register_generator", "registered_generators"]
