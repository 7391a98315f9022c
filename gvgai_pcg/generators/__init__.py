"""Constructive level generators (Justesen et al. 2018, GENERATORS.md §1).

Each game's generator lives in its folder (``gvgai_pcg.games.<game>.generator``) and is named by
its ``GameSpec``; other packages add generators through the ``gvgai_pcg.generators`` entry-point
group. This package holds the kit generators share (``_common``) and the readers of the one
registry (``gvgai_pcg.games.registry``): ``generate_level(game, difficulty, seed)`` is the entry
point. It imports no generator, so a game folder can import the kit without a cycle.
"""

from gvgai_pcg.games.registry import (
    check_difficulty,
    check_seed,
    generate_level,
    get_generator,
    register_generator,
    registered_generators,
)

__all__ = [
    "check_difficulty",
    "check_seed",
    "generate_level",
    "get_generator",
    "register_generator",
    "registered_generators",
]
