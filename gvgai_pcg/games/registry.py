"""The one registry: game names to ``GameSpec``, and generator names to generators.

Where games come from, in order:

* every folder ``gvgai_pcg/games/<name>/`` whose ``__init__.py`` defines ``SPEC`` (the four
  games of the study), found on first use;
* the modules of ``GAME_PROVIDERS``, each of several games: its ``SPECS()`` gives their specs
  (``gvgai_pcg.vgdl.corpus_games``: the GVGAI corpus games whose VGDL file the folder named by
  ``GVGAI_VGDL_DIR`` holds), found on first use and imported by name like the game folders, and
  its ``refusal(name)`` says in one line why a game of its own is not registered (what to set,
  or what the engine lacks);
* ``register_game_spec(spec)``, in-process;
* the entry-point group ``gvgai_pcg.games`` of installed packages: an entry point names a game
  and loads its ``GameSpec``.

A game's own generator is registered under the game's name. Other generators (a second generator
for a game, a plugin's) register under their own names with ``register_generator`` or through
the entry-point group ``gvgai_pcg.generators``, which loads the function. Entry points are read
when a name is missing (the games' also once per process), so installing a plugin needs no
change here, and a plugin never replaces a registered name. ``generate_level`` is the checked
front door of generation: it refuses a difficulty outside [0, 1] and a seed that is not a
non-negative integer before a generator runs.

A game may also name an editor (``GameSpec.editor``): ``level_editor(game)`` imports it on first
use, for curricula that edit the levels they replay (ACCEL).

Importing this module imports neither torch nor any game: the rules are imported when
``get_game`` first asks for them.
"""

from __future__ import annotations

import math
import numbers
import operator
import pkgutil
import warnings
from collections.abc import Callable
from importlib import import_module
from importlib.metadata import entry_points
from typing import TYPE_CHECKING

from gvgai_pcg.games.spec import Editor, GameSpec, Generator, load_object
from gvgai_pcg.plugins import load_entry_points

if TYPE_CHECKING:
    from gvgai_pcg.games.base import Game
    from gvgai_pcg.levels.level import Level

GAME_ENTRY_POINT_GROUP = "gvgai_pcg.games"
ENTRY_POINT_GROUP = "gvgai_pcg.generators"
BUILTIN_PACKAGE = "gvgai_pcg.games"
# modules of several games each (``SPECS()``, ``refusal(name)``), imported by name on first use
GAME_PROVIDERS = ("gvgai_pcg.vgdl.corpus_games",)

_SPECS: dict[str, GameSpec] = {}
_GAMES: dict[str, Game] = {}  # the rules of each game, made on first use
_RULES: dict[str, type] = {}  # classes named by @register_game
_GENERATORS: dict[str, Generator] = {}  # generators by name: the games' own (once loaded) and others
_EDITORS: dict[str, Editor] = {}  # the games' editors, imported on first use
_REFUSALS: list[Callable[[str], str | None]] = []  # game folders' reasons a game of theirs is missing
_found_builtins = False
_read_game_entry_points = False


# --- games ------------------------------------------------------------------------------------


def register_game_spec(spec: GameSpec) -> GameSpec:
    """Register ``spec``; a name that is taken by another spec is refused."""
    _find_builtin_games()
    existing = _SPECS.get(spec.name)
    if existing == spec:
        return existing
    if existing is not None:
        raise ValueError(f"game {spec.name!r} is already registered (by {existing.rules!r})")
    if spec.name in _GENERATORS and spec.generator is not None:
        raise ValueError(
            f"a generator named {spec.name!r} is already registered; a game cannot take its name"
        )
    _SPECS[spec.name] = spec
    return spec


def _find_builtin_games() -> None:
    """Register the ``SPEC`` of every game folder under gvgai_pcg/games/ and the ``SPECS()`` of
    every game provider (once)."""
    global _found_builtins
    if _found_builtins:
        return
    _found_builtins = True
    package = import_module(BUILTIN_PACKAGE)
    for module in pkgutil.iter_modules(package.__path__):
        if module.ispkg:
            spec = getattr(import_module(f"{BUILTIN_PACKAGE}.{module.name}"), "SPEC", None)
            if isinstance(spec, GameSpec):
                _SPECS.setdefault(spec.name, spec)
    for name in GAME_PROVIDERS:
        provider = import_module(name)
        for spec in provider.SPECS():
            _SPECS.setdefault(spec.name, spec)
        if provider.refusal not in _REFUSALS:
            _REFUSALS.append(provider.refusal)


def _discover_games(again: bool = False) -> None:
    """Register every entry point of ``gvgai_pcg.games`` whose game is not registered yet: once
    per process, or ``again`` (for a name that is missing). Reading the entry points costs tens
    of milliseconds, and level loading asks for the list of games for every file."""
    global _read_game_entry_points
    if _read_game_entry_points and not again:
        return
    _read_game_entry_points = True
    load_entry_points(GAME_ENTRY_POINT_GROUP, "game", GameSpec, _SPECS, register_game_spec, same=operator.eq)


def registered_games() -> list[str]:
    """Names of all games, ours and plugins', sorted."""
    _find_builtin_games()
    _discover_games()
    return sorted(_SPECS)


def study_games() -> list[str]:
    """The games of the study, in the study's order (Zelda, Solarfox, Frogs, Boulderdash)."""
    specs = [_SPECS[name] for name in registered_games() if _SPECS[name].study_index is not None]
    return [spec.name for spec in sorted(specs, key=lambda spec: spec.study_index)]


def get_game_spec(name: str) -> GameSpec:
    """The spec of game ``name``; an unknown name is refused with the registered names."""
    _find_builtin_games()
    if name not in _SPECS:
        _discover_games(again=True)
    if name in _SPECS:
        return _SPECS[name]
    known = ", ".join(sorted(_SPECS))
    reason = next((line for line in (refusal(name) for refusal in _REFUSALS) if line), None)
    raise ValueError(reason or f"unknown game {name!r}; registered games are: {known}")


def find_game_spec(name: str) -> GameSpec | None:
    """The spec of game ``name``, or ``None`` if no such game is registered."""
    try:
        return get_game_spec(name)
    except ValueError:
        return None


def register_game(name: str) -> Callable[[type[Game]], type[Game]]:
    """Class decorator: ``cls`` is the rules of game ``name`` (sets ``cls.name``). The game itself
    is registered by its ``GameSpec``, which names the class."""

    def decorate(cls: type[Game]) -> type[Game]:
        existing = _RULES.get(name)
        if existing is not None and existing is not cls:
            raise ValueError(
                f"game {name!r} is already registered ({existing.__module__}.{existing.__qualname__})"
            )
        cls.name = name
        _RULES[name] = cls
        return cls

    return decorate


def get_game(name: str) -> Game:
    """The rules of game ``name`` (one instance per process)."""
    game = _GAMES.get(name)
    if game is None:
        cls = load_object(get_game_spec(name).rules)
        if getattr(cls, "name", None) != name:
            register_game(name)(cls)
        game = _GAMES[name] = cls()
    return game


# --- generators -------------------------------------------------------------------------------


def register_generator(name: str) -> Callable[[Generator], Generator]:
    """Decorator registering ``generate(difficulty, seed) -> Level`` under ``name``; the name of a
    registered generator (a game's own included) is refused."""

    def decorate(generate: Generator) -> Generator:
        existing = _GENERATORS.get(name)
        if existing is None and _game_generator(name) is not None:
            existing = _generator_of(name)
        if existing is not None and existing is not generate:
            raise ValueError(f"a generator named {name!r} is already registered ({existing.__module__})")
        _GENERATORS[name] = generate
        return generate

    return decorate


def _game_generator(name: str) -> str | Generator | None:
    spec = find_game_spec(name)
    return None if spec is None else spec.generator


def _generator_of(game: str) -> Generator:
    """The generator of ``game``'s spec, imported once and kept under the game's name."""
    generate = _GENERATORS.get(game)
    if generate is None:
        generate = _GENERATORS[game] = load_object(_game_generator(game))
    return generate


def _discover_generators() -> None:
    """Register every entry point of ``gvgai_pcg.generators`` that is not registered yet."""
    for entry_point in entry_points(group=ENTRY_POINT_GROUP):
        if entry_point.name in _GENERATORS or _game_generator(entry_point.name) is not None:
            warnings.warn(
                f"generator plugin {entry_point.value!r} ignored: {entry_point.name!r} is already registered",
                stacklevel=3,
            )
            continue
        _GENERATORS[entry_point.name] = entry_point.load()


def registered_generators() -> list[str]:
    """Names of all generators, the games' own and plugins', sorted."""
    _discover_generators()
    games = [name for name in registered_games() if _SPECS[name].generator is not None]
    return sorted(set(_GENERATORS) | set(games))


def get_generator(name: str) -> Generator:
    """The generator registered as ``name``; an unknown name is refused with the valid names."""
    if name in _GENERATORS:
        return _GENERATORS[name]
    if _game_generator(name) is not None:
        return _generator_of(name)
    _discover_generators()
    try:
        return _GENERATORS[name]
    except KeyError:
        names = ", ".join(registered_generators())
        raise ValueError(f"no level generator named {name!r}; registered generators are: {names}") from None


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


# --- editors ----------------------------------------------------------------------------------


def level_editor(game: str) -> Editor:
    """The editor of ``game`` (``edit(level, seed) -> Level``), imported once; a game without one
    is refused with the games that have one."""
    edit = _EDITORS.get(game)
    if edit is None:
        spec = find_game_spec(game)
        if spec is None or spec.editor is None:
            having = [name for name in registered_games() if _SPECS[name].editor is not None]
            raise ValueError(
                f"no level editor for game {game!r}; games with an editor are: {', '.join(having) or 'none'}"
            )
        edit = _EDITORS[game] = load_object(spec.editor)
    return edit
