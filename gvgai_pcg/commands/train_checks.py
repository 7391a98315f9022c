"""The checks of a ``gvgai-pcg train`` command line that need neither Hydra nor torch.

A config group option that does not exist (``regimen=ppgc``, ``game=zeldaa``), a log backend
whose package is not installed and an ``out_dir`` that is a file are refused here, in one line
and well under a second, before Hydra is imported or any run directory is written. Everything
else (values, keys, sweeps with functions or interpolations) is composed and checked by
``gvgai_pcg.config.check_jobs``.
"""

from __future__ import annotations

from pathlib import Path

from gvgai_pcg.config_rules import searchpath_dirs
from gvgai_pcg.curricula.registry import curriculum_names
from gvgai_pcg.games import registered_games
from gvgai_pcg.log_backends import check_installed

# Hydra flags after which the configs come from elsewhere, or no run starts: nothing to check here.
ELSEWHERE = {"-cp", "--config-path", "-cd", "--config-dir", "-h", "--help", "--hydra-help", "--info"}
# characters of Hydra's override grammar that a plain option or list never holds
GRAMMAR = set("()${}*:")


def check_argv(argv: list[str], conf: Path) -> None:
    """``ValueError`` for the first override of ``argv`` naming a group option that ``conf`` lacks
    or a log backend that is not installed."""
    if any(arg.split("=", 1)[0] in ELSEWHERE for arg in argv):
        return
    groups = {path.name: path for path in conf.iterdir() if path.is_dir() and path.name != "hydra"}
    yours = searchpath_dirs(argv)
    for arg in argv:
        if arg.startswith(("-", "~")) or "=" not in arg:
            continue
        key, value = arg.lstrip("+").split("=", 1)
        if GRAMMAR & set(value):
            continue
        key = key.split("@", 1)[0]
        if key == "out_dir" and Path(value).exists() and not Path(value).is_dir():
            raise ValueError(f"out_dir={value}: a file; expected a folder for the run directories")
        if key in groups:
            check_group_option(key, value, groups[key], yours)
        elif key == "log.backends":
            check_installed(
                name.strip(" '\"") for name in value.replace("[", ",").replace("]", ",").split(",")
            )


def check_group_option(group: str, value: str, folder: Path, yours: tuple[Path, ...] = ()) -> None:
    """Each option of ``value`` (a comma-separated sweep with ``-m``) is a config of ``folder``, of
    the same group in one of the user's config folders ``yours`` (``hydra.searchpath``), or of a
    registered plug-in (a curriculum or a learner from outside the package, whose yaml is in no
    folder): the registry is only read for a name the folders lack, so built-in names stay fast."""
    choices = sorted(
        path.stem for place in (folder, *(f / group for f in yours)) for path in place.glob("*.yaml")
    )
    for option in value.split(","):
        option = option.strip()
        if not option or option == "null" or option in choices:
            continue
        choices = sorted(set(choices) | set(_plugins(group, folder.parent)))
        if option not in choices:
            raise ValueError(f"{group}={option}: no such {group}; the choices are {', '.join(choices)}")


def _plugins(group: str, conf: Path) -> list[str]:
    """The registered plug-ins of a config group (``regimen``: curricula, ``algo``: learners,
    ``condition``: each game with each plug-in curriculum, one whose yaml ``conf/regimen`` lacks)."""
    if group == "regimen":
        return curriculum_names()  # names only: the modules behind them import torch
    if group == "condition":
        plugins = [name for name in curriculum_names() if not (conf / "regimen" / f"{name}.yaml").is_file()]
        return [f"{game}-{name}" for name in plugins for game in registered_games()]
    if group == "algo":
        from gvgai_pcg.rl.learners.registry import registered_learners

        return list(registered_learners())
    return []
