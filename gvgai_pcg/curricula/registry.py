"""The curricula by name: ours (``gvgai_pcg.curricula.builtin``, and every other module of this
package that defines ``CURRICULUM``), those registered in-process (``register_curriculum``),
and those of installed packages through the entry-point group ``gvgai_pcg.curricula`` (an entry
point names a curriculum and loads its ``Curriculum``), read when a name is missing, as games
are (``gvgai_pcg.games.registry``).

A plug-in's config (``Curriculum.config``, a yaml file) becomes the ``regimen`` group's option of
its name in Hydra's config store (``store_configs``), so ``gvgai-pcg train regimen=<name>``
finds it without a file in ``conf/regimen/``; and each game with it a condition ``<game>-<name>``
(the ``condition`` group: the game and the curriculum), so ``gvgai-pcg reproduce --conditions
zelda-<name>`` compares it with the study's curricula as ``conf/condition/zelda-plr.yaml`` does PLR⊥.
"""

from __future__ import annotations

import pkgutil
from importlib import import_module
from pathlib import Path

from gvgai_pcg.curricula.base import Curriculum
from gvgai_pcg.curricula.builtin import BUILTIN_CURRICULA
from gvgai_pcg.games import registered_games
from gvgai_pcg.plugins import load_entry_points

ENTRY_POINT_GROUP = "gvgai_pcg.curricula"
CONFIG_GROUP = "regimen"  # the config group a curriculum is chosen by (kept: runs name it)
CONDITION_GROUP = "condition"  # a game and a curriculum together (conf/condition/<game>-<name>.yaml)

# modules that hold no curriculum
_INFRASTRUCTURE = {"base", "builtin", "level_buffer", "registry", "signals", "state"}
_CURRICULA: dict[str, Curriculum] = {}
_read_entry_points = False


def _builtins() -> None:
    """Register the study's curricula (once; light: nothing of torch)."""
    if _CURRICULA:
        return
    for curriculum in BUILTIN_CURRICULA:
        _CURRICULA[curriculum.name] = curriculum


def _package_modules() -> list[str]:
    """The modules of this package that define a curriculum, each of its own name."""
    package = import_module(__package__)
    return [m.name for m in pkgutil.iter_modules(package.__path__) if m.name not in _INFRASTRUCTURE]


def _curriculum_name(module: str) -> str:
    """The name of the curriculum ``module`` defines: its own, hyphens for underscores (a module
    name cannot hold a hyphen: ``accel_noselect.py`` holds ``accel-noselect``)."""
    return module.replace("_", "-")


def _ours(names: list[str] | None = None) -> None:
    """Register the ``CURRICULUM`` of the package's modules ``names`` (default: all). Imported only
    when asked for, since they import torch, so that reading configs and refusing a usage error
    stay fast."""
    _builtins()
    for name in _package_modules() if names is None else names:
        curriculum = getattr(import_module(f"{__package__}.{name}"), "CURRICULUM", None)
        if isinstance(curriculum, Curriculum):
            _CURRICULA.setdefault(curriculum.name, curriculum)


def register_curriculum(curriculum: Curriculum) -> Curriculum:
    """Register ``curriculum`` under its name; a name taken by another curriculum is refused."""
    _builtins()
    if not isinstance(curriculum, Curriculum) or not curriculum.name:
        raise ValueError(f"expected a named Curriculum instance, got {curriculum!r}")
    existing = _CURRICULA.get(curriculum.name)
    if existing is not None and existing is not curriculum:
        raise ValueError(f"curriculum {curriculum.name!r} is already registered ({type(existing).__name__})")
    _CURRICULA[curriculum.name] = curriculum
    return curriculum


def unregister_curriculum(name: str) -> None:
    """Forget the curriculum ``name`` (tests of plug-ins clean up with it)."""
    _CURRICULA.pop(name, None)


def _discover(again: bool = False) -> None:
    """Register every entry point of ``gvgai_pcg.curricula`` whose name is free: once per
    process, or ``again`` (for a missing name)."""
    global _read_entry_points
    if _read_entry_points and not again:
        return
    _read_entry_points = True
    _builtins()
    load_entry_points(ENTRY_POINT_GROUP, "curriculum", Curriculum, _CURRICULA, register_curriculum)


def registered_curricula() -> dict[str, Curriculum]:
    """Every curriculum by name: ours first, in the study's order, then plug-ins'."""
    _ours()
    _discover()
    return dict(_CURRICULA)


def curriculum_names() -> list[str]:
    """Every curriculum's name without importing the modules that define them, so that a usage
    error can list the choices before torch is imported: ours (a module of this package defines
    the curriculum of its own name: ``plr.py`` holds ``plr``, ``accel_noselect.py``
    ``accel-noselect``), those registered in-process, and
    the entry points' names."""
    from importlib.metadata import entry_points

    names = [curriculum.name for curriculum in BUILTIN_CURRICULA] + [
        _curriculum_name(m) for m in _package_modules()
    ]
    names += list(_CURRICULA) + [point.name for point in entry_points(group=ENTRY_POINT_GROUP)]
    return list(dict.fromkeys(names))


def get_curriculum(name: str) -> Curriculum:
    """The curriculum ``name``; an unknown name is refused with the registered ones."""
    _builtins()
    modules = {_curriculum_name(module): module for module in _package_modules()}
    if name not in _CURRICULA and name in modules:
        _ours([modules[name]])
    if name not in _CURRICULA:
        _discover(again=True)
    try:
        return _CURRICULA[name]
    except KeyError:
        raise ValueError(
            f"unknown regimen {name!r}; valid regimens are: {', '.join(curriculum_names())}"
        ) from None


def plugin_curricula(config_dir: Path | None = None) -> list[Curriculum]:
    """The registered curricula with a yaml of their own (``Curriculum.config``) that is not ours
    (``config_dir/regimen/<name>.yaml``): plug-ins. Ours are not imported (that costs torch)."""
    _discover()
    return [
        c
        for c in _CURRICULA.values()
        if c.config is not None
        and not (config_dir is not None and (config_dir / CONFIG_GROUP / f"{c.name}.yaml").is_file())
    ]


def plugin_conditions(config_dir: Path | None = None) -> dict[str, tuple[str, str]]:
    """``<game>-<name> -> (game, name)``: the condition of every registered game with every
    plug-in curriculum, but those ``config_dir/condition`` has a yaml of."""
    conditions = {
        f"{game}-{curriculum.name}": (game, curriculum.name)
        for curriculum in plugin_curricula(config_dir)
        for game in registered_games()
    }
    if config_dir is None:
        return conditions
    return {
        c: pair
        for c, pair in conditions.items()
        if not (config_dir / CONDITION_GROUP / f"{c}.yaml").is_file()
    }


def store_configs(config_dir: Path | None = None) -> None:
    """Put the yaml of every plug-in curriculum into Hydra's config store as the option ``name``
    of the ``regimen`` group, unless ``config_dir/regimen/<name>.yaml`` exists (ours), and its
    condition with every game as the option ``<game>-<name>`` of the ``condition`` group."""
    plugins = plugin_curricula(config_dir)  # ours have their yaml in conf/regimen
    if not plugins:
        return
    from hydra.core.config_store import ConfigStore
    from omegaconf import OmegaConf

    store = ConfigStore.instance()
    for curriculum in plugins:
        node = OmegaConf.load(Path(curriculum.config))
        store.store(group=CONFIG_GROUP, name=curriculum.name, node=node, provider="gvgai_pcg.curricula")
    for condition, (game, name) in plugin_conditions(config_dir).items():
        node = OmegaConf.create({"defaults": [{"override /game": game}, {f"override /{CONFIG_GROUP}": name}]})
        store.store(
            group=CONDITION_GROUP,
            name=condition,
            node=node,
            package="_global_",
            provider="gvgai_pcg.curricula",
        )
