"""The curricula by name: ours (``gvgai_pcg.curricula.builtin``, and every other module of this
package that defines ``CURRICULUM``), those registered in-process (``register_curriculum``),
and those of installed packages through the entry-point group ``gvgai_pcg.curricula`` (an entry
point names a curriculum and loads its ``Curriculum``), read when a name is missing, as games
are (``gvgai_pcg.games.registry``).

A plug-in's config (``Curriculum.config``, a yaml file) becomes the ``regimen`` group's option of
its name in Hydra's config store (``store_configs``), so ``gvgai-pcg train regimen=<name>``
finds it without a file in ``conf/regimen/``.
"""

from __future__ import annotations

import pkgutil
from importlib import import_module
from pathlib import Path

from gvgai_pcg.curricula.base import Curriculum
from gvgai_pcg.plugins import load_entry_points

ENTRY_POINT_GROUP = "gvgai_pcg.curricula"
CONFIG_GROUP = "regimen"  # the config group a curriculum is chosen by (kept: runs name it)

# modules that hold no curriculum
_INFRASTRUCTURE = {"base", "builtin", "level_buffer", "registry", "signals", "state"}
_CURRICULA: dict[str, Curriculum] = {}
_read_entry_points = False


def _builtins() -> None:
    """Register the study's curricula, then the ``CURRICULUM`` of every other module here (once)."""
    if _CURRICULA:
        return
    from gvgai_pcg.curricula.builtin import BUILTIN_CURRICULA

    for curriculum in BUILTIN_CURRICULA:
        _CURRICULA[curriculum.name] = curriculum
    package = import_module(__package__)
    for module in pkgutil.iter_modules(package.__path__):
        if module.name not in _INFRASTRUCTURE:
            curriculum = getattr(import_module(f"{__package__}.{module.name}"), "CURRICULUM", None)
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
    _discover()
    return dict(_CURRICULA)


def get_curriculum(name: str) -> Curriculum:
    """The curriculum ``name``; an unknown name is refused with the registered ones."""
    _builtins()
    if name not in _CURRICULA:
        _discover(again=True)
    try:
        return _CURRICULA[name]
    except KeyError:
        raise ValueError(f"unknown regimen {name!r}; valid regimens are: {', '.join(_CURRICULA)}") from None


def store_configs(config_dir: Path | None = None) -> None:
    """Put the yaml of every plug-in curriculum into Hydra's config store as the option ``name``
    of the ``regimen`` group, unless ``config_dir/regimen/<name>.yaml`` exists (ours)."""
    plugins = [c for c in registered_curricula().values() if c.config is not None]
    if not plugins:
        return
    from hydra.core.config_store import ConfigStore
    from omegaconf import OmegaConf

    store = ConfigStore.instance()
    for curriculum in plugins:
        if config_dir is not None and (config_dir / CONFIG_GROUP / f"{curriculum.name}.yaml").is_file():
            continue
        node = OmegaConf.load(Path(curriculum.config))
        store.store(group=CONFIG_GROUP, name=curriculum.name, node=node, provider="gvgai_pcg.curricula")
