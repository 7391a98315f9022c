"""The training config: where the Hydra configs are, and the schema a run is checked against.

``conf/`` is the source of the configs; a wheel ships the same files as ``gvgai_pcg/conf``, and
``config_dir`` finds whichever is there. Every composed config is checked against ``SCHEMA``
before a run starts: each key's type and range, no unknown or missing keys, the regimen's keys
for its name, and the level files of a level set parsed. A bad value is a ``ConfigError`` whose
message is one line naming the key, the value and what is allowed:
``total_frames=-5: expected an integer >= 1``.

``gvgai-pcg train`` checks every job of the command line (each run of a ``-m`` sweep) before
Hydra writes any run directory (``check_command_line``), and the task checks its own config
again (``checked_config``), which also gives back the values normalised: integers for integral
floats (``total_frames=1e6``), absolute level paths.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from omegaconf import DictConfig, OmegaConf

from gvgai_pcg.config_rules import (  # noqa: F401 (the rules are this module's API too)
    CONFIG_NAME,
    DIFFICULTY,
    HUMAN_LEVEL,
    LOG_BACKENDS,
    WIN_RULES,
    ConfigError,
    Device,
    Flag,
    Integer,
    LevelPaths,
    ListOf,
    Number,
    OneOf,
    Refused,
    Text,
    config_root,
    level_count_tag,
    level_set_tag,
)
from gvgai_pcg.curricula import registered_curricula
from gvgai_pcg.curricula.registry import store_configs as store_curriculum_configs
from gvgai_pcg.games import registered_games


def config_dir() -> Path:
    """The Hydra configs (``config_root``), with the plug-in curricula's and learners' configs stored
    in their groups."""
    candidate = config_root()
    store_curriculum_configs(candidate)  # plug-in curricula's configs join the regimen group
    _store_learner_configs(candidate)  # and plug-in learners' the algo group
    return candidate


def _store_learner_configs(candidate: Path) -> None:
    """Plug-in learners' yaml into the ``algo`` group, where there is a plug-in learner: one
    registered in-process (the learner registry is imported then) or an entry point. Without one
    nothing is imported (the learners' package imports torch; a usage error is refused before)."""
    import sys
    from importlib.metadata import entry_points

    if "gvgai_pcg.rl.learners.registry" not in sys.modules and not entry_points(group="gvgai_pcg.learners"):
        return
    from gvgai_pcg.rl.learners.registry import store_configs

    store_configs(candidate)


# --- resolvers the config files use (registered on import) ---


def learner_tag(name: Any) -> str:
    """What a run name adds for the learner: ``""`` for A2C (the study's learner, so that the
    published runs keep their names), ``-ppo`` for PPO, the spec's ``run_tag`` for a plug-in."""
    from gvgai_pcg.rl.learners import get_learner_spec

    try:
        return get_learner_spec(str(name)).tag
    except ValueError:  # refused with the registered names by the config check
        return f"-{name}"


# A training process peaks near 0.5 GB (Zelda, 64 envs, tiles, compact CNN; one collector worker
# or two); a job asks four times that per process, so the paper's pixels and Nature CNN fit too.
GB_PER_PROCESS = 2


def cpus_per_run(threads: Any, workers: Any) -> int:
    """The CPUs one run uses: its torch threads in each collector process (0 threads, torch's
    default, counts as one; say ``hydra.launcher.cpus_per_task`` where the node has it to spare)."""
    return max(int(threads), 1) * max(int(workers), 1)


def mem_gb_per_run(workers: Any) -> int:
    """The memory one run asks for: ``GB_PER_PROCESS`` for each of its collector processes."""
    return GB_PER_PROCESS * max(int(workers), 1)


for _name, _resolver in (
    ("gvgai_pcg.learner_tag", learner_tag),
    ("gvgai_pcg.cpus_per_run", cpus_per_run),
    ("gvgai_pcg.mem_gb_per_run", mem_gb_per_run),
    ("gvgai_pcg.level_count", level_count_tag),
    ("gvgai_pcg.level_set", level_set_tag),
):
    if not OmegaConf.has_resolver(_name):
        OmegaConf.register_new_resolver(_name, _resolver)


# --- the schema: one rule per leaf key ---


def _games() -> list[str]:
    return registered_games()


def _models() -> tuple[str, ...]:
    from gvgai_pcg.rl.models import MODELS

    return MODELS


# The regimen section's keys are the chosen curriculum's (gvgai_pcg.curricula: Curriculum.schema).
# win_rule is read by pcg and ppcg only; the others accept it so that preset=paper (which sets it
# for every regimen) combines with any of them.


def _regimens() -> dict[str, Any]:
    return registered_curricula()


def __getattr__(name: str) -> Any:
    if name == "REGIMENS":  # each regimen's keys and their rules, from the registered curricula
        return {key: curriculum.schema for key, curriculum in _regimens().items()}
    raise AttributeError(f"module 'gvgai_pcg.config' has no attribute {name!r}")


@dataclass(frozen=True)
class Variants:
    """A section whose keys depend on its ``name`` (the regimen group): ``variants()`` gives
    the objects by name, each with ``schema`` (its keys' rules) and ``optional`` (keys it may
    leave out)."""

    variants: Callable[[], Mapping[str, Any]]
    key: str = "name"


@dataclass(frozen=True)
class LearnerKeys:
    """The ``algo`` keys of one learner, as ``Variants`` reads them: ``name`` and its spec's schema."""

    schema: Mapping[str, Any]
    optional: frozenset[str] = frozenset()


def _learners() -> dict[str, LearnerKeys]:
    from gvgai_pcg.rl.learners import get_learner_spec, registered_learners

    return {
        name: LearnerKeys({"name": Text(), **get_learner_spec(name).schema}) for name in registered_learners()
    }


SCHEMA: dict[str, Any] = {
    "game": {"name": OneOf(_games)},
    "regimen": Variants(_regimens),
    "model": {"name": OneOf(_models), "hidden": Integer(1)},
    "algo": Variants(_learners),  # each learner declares its keys (gvgai_pcg.rl.learners)
    "seed": Integer(0, 2**32 - 1),  # numpy's seed range
    "total_frames": Integer(1),
    "device": Device(),
    "threads": Integer(0),
    "rollout": OneOf(("auto", "fused", "unfused")),
    "env": {"num_envs": Integer(1), "obs": OneOf(("tiles", "pixels")), "max_steps": Integer(1)},
    "collector": {"workers": Integer(1)},
    "checkpoint": {"every_frames": Integer(1), "keep_every_frames": Integer(0)},
    "log": {
        "every_episodes": Integer(1),
        "every_update_frames": Integer(1),
        "backends": ListOf(OneOf(LOG_BACKENDS), unique=True, min_items=0),
        "curve": Flag(),
    },
    "out_dir": Text(),
    "run_name": Text(),
}


# Keys a config written before them may lack (their default is the old behaviour).
OPTIONAL_KEYS = frozenset({"rollout"})


def _shown(value: Any) -> str:
    if isinstance(value, dict | list):
        return repr(value)
    return repr(value) if isinstance(value, str) else str(value)


def _check_section(
    values: Any, schema: Mapping[str, Any], prefix: str, out: dict, optional: frozenset[str] = frozenset()
) -> None:
    where = prefix.rstrip(".") or "the config"
    if not isinstance(values, dict):
        raise ConfigError(f"{where}={_shown(values)}: expected a section with the keys {', '.join(schema)}")
    for key, value in values.items():
        if key not in schema:
            raise ConfigError(
                f"{prefix}{key}={_shown(value)}: unknown key; the keys of {where} are {', '.join(schema)}"
            )
    for key, rule in schema.items():
        name = f"{prefix}{key}"
        if key not in values:
            if key in optional:
                continue
            what = rule.expected if hasattr(rule, "expected") else "a section"
            raise ConfigError(f"{name}: missing; expected {what}")
        value = values[key]
        if value == "???":
            raise ConfigError(f"{name}: missing (???); expected {getattr(rule, 'expected', 'a section')}")
        if isinstance(rule, Variants):
            out[key] = {}
            choice = value.get(rule.key) if isinstance(value, dict) else None
            variants = rule.variants()
            if choice not in variants:
                raise ConfigError(
                    f"{name}.{rule.key}={_shown(choice)}: expected one of {', '.join(variants)}"
                )
            variant = variants[choice]
            _check_section(value, variant.schema, f"{name}.", out[key], frozenset(variant.optional))
        elif isinstance(rule, Mapping):
            out[key] = {}
            _check_section(value, rule, f"{name}.", out[key])
        else:
            try:
                out[key] = rule.check(value)
            except Refused:
                raise ConfigError(f"{name}={_shown(value)}: expected {rule.expected}") from None


def _check_together(config: dict) -> None:
    """Rules across keys: the regimen's own (``Curriculum.check``: a generated set's seeds, a level
    set's files), the learner's (``LearnerSpec.check``: PPO's minibatches), the memory the envs
    need (``config.memory``), model and observation."""
    regimen = config["regimen"]
    _regimens()[regimen["name"]].check(regimen, config)
    from gvgai_pcg.rl.learners import get_learner_spec

    learner_check = get_learner_spec(config["algo"]["name"]).check
    if learner_check is not None:
        learner_check(config["algo"], config)
    from gvgai_pcg.config.memory import check_memory

    try:
        check_memory(config)  # env.num_envs=1000000: refused now, not by an allocation minutes in
    except ValueError as error:
        raise ConfigError(str(error)) from None
    if config["model"]["name"] == "nature" and config["env"]["obs"] != "pixels":
        raise ConfigError(
            f"env.obs={_shown(config['env']['obs'])}: expected pixels with model=nature "
            "(the study's CNN needs the pixel frames); use model=compact for tiles"
        )


def validate(cfg: DictConfig | Mapping) -> dict:
    """The config's values, checked against ``SCHEMA`` and normalised (resolved, as plain
    containers); a ``ConfigError`` for the first bad value. ``hydra`` is not checked."""
    if isinstance(cfg, DictConfig):
        missing = _missing_keys(cfg)
        if missing:
            rule = _rule_of(missing[0])
            raise ConfigError(f"{missing[0]}: missing (???); expected {getattr(rule, 'expected', 'a value')}")
        try:
            values = OmegaConf.to_container(cfg, resolve=True)
        except Exception as error:  # an interpolation that does not resolve
            key, first = getattr(error, "full_key", None) or "the config", str(error).splitlines()[0]
            raise ConfigError(f"{key}: does not resolve ({first})") from None
    else:
        values = dict(cfg)
    values.pop("hydra", None)
    checked: dict = {}
    _check_section(values, SCHEMA, "", checked, OPTIONAL_KEYS)
    _check_together(checked)
    return checked


def _missing_keys(cfg: DictConfig, prefix: str = "") -> list[str]:
    found = []
    for key in cfg:
        if key == "hydra" and not prefix:
            continue
        if OmegaConf.is_missing(cfg, key):
            found.append(f"{prefix}{key}")
        elif not OmegaConf.is_interpolation(cfg, key) and isinstance(cfg[key], DictConfig):
            found += _missing_keys(cfg[key], f"{prefix}{key}.")
    return found


def _rule_of(dotted: str) -> Any:
    rule: Any = SCHEMA
    for part in dotted.split("."):
        if isinstance(rule, Variants):
            rule = next((v.schema[part] for v in rule.variants().values() if part in v.schema), None)
        elif isinstance(rule, Mapping):
            rule = rule.get(part)
        if rule is None:
            return None
    return rule


def checked_config(cfg: DictConfig) -> DictConfig:
    """``cfg`` checked (``validate``) and with its normalised values, as a new config."""
    return OmegaConf.create(validate(cfg))


# --- composing configs, as gvgai-pcg train does ---


def compose_config(overrides: Sequence[str] = (), config_name: str = CONFIG_NAME) -> DictConfig:
    """The training config that ``gvgai-pcg train OVERRIDES`` would run, checked.

    For the Python API: ``train(compose_config(["game=frogs", "total_frames=5000"]), run_dir)``."""
    from hydra import compose, initialize_config_dir

    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3", job_name="train"):
        cfg = compose(config_name, overrides=list(overrides))
    return checked_config(cfg)


def sweep_jobs(overrides: Sequence[str], multirun: bool) -> list[list[str]]:
    """The override lists of the runs a command line starts (one without ``-m``; every
    combination of a basic sweep with it)."""
    if not multirun:
        return [list(overrides)]
    from hydra._internal.core_plugins.basic_sweeper import BasicSweeper
    from hydra.core.override_parser.overrides_parser import OverridesParser

    parsed = OverridesParser.create().parse_overrides(list(overrides))
    jobs = [tuple(job) for batch in BasicSweeper.split_arguments(parsed, None) for job in batch]
    return [list(job) for job in dict.fromkeys(jobs)]


def check_jobs(jobs: Sequence[Sequence[str]], config_name: str = CONFIG_NAME) -> bool:
    """Compose and ``validate`` the config of every job; ``ConfigError`` for the first bad one.

    Returns ``False`` (nothing checked) where a job does not compose for another reason (a group
    option that does not exist, a launcher that is not installed, bad override syntax): Hydra
    itself then reports that when it runs."""
    from hydra import compose, initialize_config_dir
    from hydra.errors import ConfigCompositionException, HydraException

    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3", job_name="train"):
        for job in jobs:
            try:
                cfg = compose(config_name, overrides=list(job))
            except (ConfigCompositionException, HydraException) as error:
                unknown = _unknown_override(error, job, config_name)
                if unknown:
                    raise ConfigError(unknown) from None
                # Hydra's own settings (a launcher's keys, a launcher this composer cannot load) do
                # not shape the run's config: it is checked without them, and Hydra judges them.
                task = [override for override in job if not _is_hydra_override(override)]
                if len(task) == len(job):
                    return False
                try:
                    cfg = compose(config_name, overrides=task)
                except (ConfigCompositionException, HydraException) as task_error:
                    unknown = _unknown_override(task_error, task, config_name)
                    if unknown:
                        raise ConfigError(unknown) from None
                    return False
            validate(cfg)
    return True


def _is_hydra_override(override: str) -> bool:
    """Whether ``override`` sets Hydra's own config (``hydra.run.dir=...``, ``hydra/launcher=...``)."""
    key = override.split("=", 1)[0].lstrip("~+")
    return key == "hydra" or key.startswith(("hydra.", "hydra/"))


def _unknown_override(error: Exception, job: Sequence[str], config_name: str) -> str | None:
    """The one-line message for an override of a key the config does not have, else ``None``."""
    from hydra import compose

    match = re.match(r"Could not override '([^']+)'", str(error))
    if not match or match.group(1).startswith("hydra."):
        return None
    key = match.group(1)
    value = next((o.split("=", 1)[1] for o in job if o.split("=", 1)[0].lstrip("~+") == key), "")
    section, _, _ = key.rpartition(".")
    rest = [o for o in job if o.split("=", 1)[0].lstrip("~+") != key]
    try:
        base = compose(config_name, overrides=rest)
        keys = list(OmegaConf.select(base, section) if section else (k for k in base if k != "hydra"))
    except Exception:
        keys = []
    where = section or "the config"
    listed = f"; the keys of {where} are {', '.join(map(str, keys))}" if keys else ""
    return f"{key}={value}: unknown key{listed}"
