"""The generator registry: game name -> ``generate(difficulty, seed) -> Level``.

Our own generators register with ``@register_generator("zelda")``; other packages add theirs
through the ``gvgai_pcg.generators`` entry-point group (the entry point names the game and loads
the generate function). Entry points are looked up when a name is missing, so installing a
plugin needs no change here. ``generate_level`` is the checked front door: it refuses a
difficulty outside [0, 1] and a seed that is not a non-negative integer before any generator runs.
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Callable
from importlib.metadata import entry_points

from gvgai_pcg.levels.level import Level

ENTRY_POINT_GROUP = "gvgai_pcg.generators"

Generator = Callable[[float, int], Level]

_GENERATORS: dict[str, Generator] = {}


def register_generator(name: str) -> Callable[[Generator], Generator]:
    """Decorator registering ``generate(difficulty, seed) -> Level`` under ``name``."""

    def decorate(generate: Generator) -> Generator:
        existing = _GENERATORS.get(name)
        if existing is not None and existing is not generate:
            raise ValueError(f"a generator named {name!r} is already registered ({existing.__module__})")
        _GENERATORS[name] = generate
        return generate

    return decorate


def _discover_plugins() -> None:
    """Register every entry point of the group that is not registered yet."""
    for entry_point in entry_points(group=ENTRY_POINT_GROUP):
        if entry_point.name in _GENERATORS:
            warnings.warn(
                f"generator plugin {entry_point.value!r} ignored: {entry_point.name!r} is already registered",
                stacklevel=3,
            )
            continue
        _GENERATORS[entry_point.name] = entry_point.load()


def registered_generators() -> list[str]:
    """Names of all generators, our own and plugins', sorted."""
    _discover_plugins()
    return sorted(_GENERATORS)


def get_generator(name: str) -> Generator:
    """The generator registered as ``name``; an unknown name is refused with the valid names."""
    if name not in _GENERATORS:
        _discover_plugins()
    try:
        return _GENERATORS[name]
    except KeyError:
        raise ValueError(
            f"no level generator named {name!r}; registered generators are: {', '.join(sorted(_GENERATORS))}"
        ) from None


def check_difficulty(difficulty: object) -> float:
    """``difficulty`` as a float, or ValueError unless it is a real number in [0, 1]."""
    if isinstance(difficulty, bool) or not isinstance(difficulty, numbers.Real):
        raise ValueError(f"difficulty must be a number in [0, 1], got {difficulty!r}")
    value = float(difficulty)
    if math.isnan(value) or not 0.0 <= value <= 1.0:
        raise ValueError(f"difficulty must be a number in [0, 1], got {difficulty!r}")
    return value


def check_seed(seed: object) -> int:
    """``seed`` as an int, or ValueError unless it is a non-negative integer (numpy ints are fine)."""
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
        raise ValueError(f"seed must be a non-negative integer, got {seed!r} ({type(seed).__name__})")
    if seed < 0:
        raise ValueError(f"seed must be a non-negative integer (>= 0), got {seed!r}")
    return int(seed)


def generate_level(game: str, difficulty: float, seed: int) -> Level:
    """A level of ``game`` at ``difficulty`` in [0, 1]; the same (game, d, seed) gives the same level."""
    generate = get_generator(game)
    return generate(check_difficulty(difficulty), check_seed(seed))
