"""The learner registry: ``algo.name`` to ``LearnerSpec``, as ``gvgai_pcg.games.registry`` is for games.

Where learners come from, in order: the built-in ones (A2C, PPO), ``register_learner(spec)``
in-process, and the entry-point group ``gvgai_pcg.learners`` of installed packages (an entry
point named like the learner loads its ``LearnerSpec``). A name is never replaced. Importing this
module imports neither torch nor a learner's code: ``learner_class`` imports it when a run starts.
"""

from __future__ import annotations

import operator
from pathlib import Path

from gvgai_pcg.games.spec import load_object
from gvgai_pcg.plugins import load_entry_points
from gvgai_pcg.rl.learners.spec import LearnerSpec

LEARNER_ENTRY_POINT_GROUP = "gvgai_pcg.learners"
BUILTIN_SPECS = ("gvgai_pcg.rl.learners.a2c:SPEC", "gvgai_pcg.rl.learners.ppo:SPEC")

_SPECS: dict[str, LearnerSpec] = {}
_found_builtins = False


def _find_builtins() -> None:
    global _found_builtins
    if not _found_builtins:
        _found_builtins = True
        for path in BUILTIN_SPECS:
            spec = load_object(path)
            _SPECS.setdefault(spec.name, spec)


def register_learner(spec: LearnerSpec) -> LearnerSpec:
    """Register ``spec``; a name taken by another spec is refused."""
    _find_builtins()
    existing = _SPECS.get(spec.name)
    if existing is not None and existing != spec:
        raise ValueError(f"learner {spec.name!r} is already registered (by {existing.learner!r})")
    _SPECS[spec.name] = spec
    return spec


def _discover() -> None:
    load_entry_points(LEARNER_ENTRY_POINT_GROUP, "learner", LearnerSpec, _SPECS, _add, same=operator.eq)


def _add(spec: LearnerSpec) -> None:
    _SPECS[spec.name] = spec


def registered_learners() -> list[str]:
    """Names of all learners, ours and plugins', sorted."""
    _find_builtins()
    _discover()
    return sorted(_SPECS)


def get_learner_spec(name: str) -> LearnerSpec:
    """The spec of learner ``name``; an unknown name is refused with the registered names."""
    _find_builtins()
    if name not in _SPECS:
        _discover()
    try:
        return _SPECS[name]
    except KeyError:
        raise ValueError(
            f"unknown learner {name!r} (algo.name); registered learners are: {', '.join(sorted(_SPECS))}"
        ) from None


def learner_class(name: str) -> type:
    """The ``Learner`` class of learner ``name`` (imported now)."""
    spec = get_learner_spec(name)
    return load_object(spec.learner) if isinstance(spec.learner, str) else spec.learner


def run_tag(name: str) -> str:
    """What ``run_name`` adds for learner ``name`` (``""`` for A2C, ``"-ppo"`` for PPO)."""
    return get_learner_spec(name).tag


def store_configs(config_dir: Path | None = None) -> None:
    """Put the yaml of every plug-in learner (``LearnerSpec.config``) into Hydra's config store as
    the ``algo`` group's option of its name, unless ``config_dir/algo/<name>.yaml`` exists (ours).
    Ours are not imported for it (they import torch; their yaml is in ``conf/algo``)."""
    _discover()
    plugins = [spec for spec in _SPECS.values() if spec.config is not None]
    if not plugins:
        return
    from hydra.core.config_store import ConfigStore
    from omegaconf import OmegaConf

    store = ConfigStore.instance()
    for spec in plugins:
        if config_dir is not None and (config_dir / "algo" / f"{spec.name}.yaml").is_file():
            continue
        store.store(
            group="algo",
            name=spec.name,
            node=OmegaConf.load(Path(spec.config)),
            provider="gvgai_pcg.learners",
        )
