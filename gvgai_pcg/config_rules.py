"""The rules of the training config's schema, and the values and tags the config files use.

Apart from ``gvgai_pcg.config`` so that what declares a schema (a curriculum, a learner) can use
these rules without importing the config checks, which read the registered curricula and
learners: the rules import nothing of the package.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any


class ConfigError(ValueError):
    """A config that cannot train; the message is one line: key, value, what is allowed."""


def level_count_tag(num_levels: Any, start_seed: Any = 0) -> str:
    """``""`` for unlimited levels, ``-n100`` for a set of 100, ``-n100-s7`` starting at seed 7."""
    if num_levels in (0, "0", None):
        return ""
    return f"-n{num_levels}" + (f"-s{start_seed}" if start_seed not in (0, "0", None) else "")


def level_set_tag(path: Any) -> str:
    """The name of a level set in a run name: the folder's or file's name (``mine``), the first
    file's and how many more for a list (``a+2``)."""
    paths = [path] if isinstance(path, str) else list(path or [])
    if not paths:
        return "none"
    first = Path(str(paths[0]).rstrip("/\\"))
    name = first.stem if first.suffix == ".txt" else first.name
    return name + (f"+{len(paths) - 1}" if len(paths) > 1 else "")


class Refused(Exception):
    """A value a rule does not accept (``ConfigError`` is raised with the key added)."""


@dataclass(frozen=True)
class Integer:
    low: int | None = None
    high: int | None = None

    @property
    def expected(self) -> str:
        if self.low is not None and self.high is not None:
            return f"an integer in [{self.low}, {self.high}]"
        if self.low is not None:
            return f"an integer >= {self.low}"
        return "an integer"

    def check(self, value: Any) -> int:
        if isinstance(value, float) and value.is_integer():
            value = int(value)  # total_frames=1e6
        if isinstance(value, bool) or not isinstance(value, int):
            raise Refused
        if (self.low is not None and value < self.low) or (self.high is not None and value > self.high):
            raise Refused
        return value


@dataclass(frozen=True)
class Number:
    low: float | None = None
    high: float | None = None
    low_open: bool = False  # low itself is not allowed

    @property
    def expected(self) -> str:
        if self.low is not None and self.high is not None:
            return f"a number in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}]"
        if self.low is not None:
            return f"a finite number {'>' if self.low_open else '>='} {self.low:g}"
        return "a finite number"

    def check(self, value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise Refused
        if self.low is not None and (value < self.low or (self.low_open and value == self.low)):
            raise Refused
        if self.high is not None and value > self.high:
            raise Refused
        return float(value)


@dataclass(frozen=True)
class OneOf:
    choices: tuple[str, ...] | Callable[[], Sequence[str]]

    @property
    def options(self) -> tuple[str, ...]:
        return tuple(self.choices() if callable(self.choices) else self.choices)

    @property
    def expected(self) -> str:
        return "one of " + ", ".join(self.options)

    def check(self, value: Any) -> str:
        if not isinstance(value, str) or value not in self.options:
            raise Refused
        return value


@dataclass(frozen=True)
class Text:
    expected: str = "a non-empty string"

    def check(self, value: Any) -> str:
        if not isinstance(value, str) or not value.strip():
            raise Refused
        return value


@dataclass(frozen=True)
class Flag:
    expected: str = "true or false"

    def check(self, value: Any) -> bool:
        if not isinstance(value, bool):
            raise Refused
        return value


@dataclass(frozen=True)
class ListOf:
    item: Any
    unique: bool = False
    min_items: int = 1

    @property
    def expected(self) -> str:
        size = "a non-empty list" if self.min_items else "a list"
        return f"{size}{' without repeats' if self.unique else ''}, each {self.item.expected}"

    def check(self, value: Any) -> list:
        if not isinstance(value, list | tuple) or len(value) < self.min_items:
            raise Refused
        checked = [self.item.check(v) for v in value]
        if self.unique and len(set(checked)) != len(checked):
            raise Refused
        return checked


@dataclass(frozen=True)
class Device:
    expected: str = "cpu, cuda, cuda:N or mps, present on this machine"

    def check(self, value: Any) -> str:
        import torch

        if not isinstance(value, str) or not re.fullmatch(r"cpu|mps|cuda(:\d+)?", value):
            raise Refused
        if value.startswith("cuda"):
            index = int(value.partition(":")[2] or 0)
            if not torch.cuda.is_available() or index >= torch.cuda.device_count():
                raise Refused
        if value == "mps" and not torch.backends.mps.is_available():
            raise Refused
        return value


@dataclass(frozen=True)
class LevelPaths:
    """A level set: a folder of ``.txt`` level files, one file, or a list of files and folders."""

    expected: str = "a folder of level files, a level file, or a non-empty list of them"

    def check(self, value: Any) -> str | list[str]:
        if isinstance(value, str) and value.strip():
            return str(Path(value).expanduser().resolve())
        if isinstance(value, list | tuple) and value and all(isinstance(v, str) and v.strip() for v in value):
            return [str(Path(v).expanduser().resolve()) for v in value]
        raise Refused


WIN_RULES = ("game", "study")
LOG_BACKENDS = ("csv", "tensorboard", "wandb")
HUMAN_LEVEL = Integer(0, 4)
DIFFICULTY = Number(0.0, 1.0)


CONFIG_NAME = "config"


def config_root() -> Path:
    """The folder of the Hydra configs, found without registering anything (``gvgai_pcg.config``'s
    ``config_dir`` also stores the plug-ins' configs): ``gvgai_pcg/conf`` of an installed wheel,
    else ``conf/`` of the source checkout this package runs from (an editable install)."""
    package = Path(__file__).resolve().parent
    for candidate in (package / "conf", package.parent / "conf"):
        if (candidate / f"{CONFIG_NAME}.yaml").is_file():
            return candidate
    raise FileNotFoundError(
        f"the Hydra configs are missing: looked for {CONFIG_NAME}.yaml in {package / 'conf'} (an installed "
        f"wheel) and {package.parent / 'conf'} (a source checkout); reinstall gvgai-pcg"
    )


# Where a user's own configs join ours: Hydra searches each ``file://`` folder of this override
# after the package's configs (``reproduce --config-dir DIR`` adds it to every run).
SEARCHPATH = "hydra.searchpath"
FILE_SCHEME = "file://"


def searchpath_override(folder: Path) -> str:
    """The Hydra override that makes every run search ``folder`` for configs after ours."""
    return f"{SEARCHPATH}=[{FILE_SCHEME}{Path(folder).resolve()}]"


def searchpath_dirs(overrides: Sequence[str]) -> tuple[Path, ...]:
    """The folders that ``hydra.searchpath`` overrides among ``overrides`` add (``file://`` ones;
    a package's, ``pkg://``, holds no user's conditions)."""
    folders: list[Path] = []
    for override in overrides:
        key, _, value = override.lstrip("+").partition("=")
        if key != SEARCHPATH:
            continue
        for entry in value.strip().strip("[]").split(","):
            entry = entry.strip().strip("'\"")
            if entry.startswith(FILE_SCHEME):
                folders.append(Path(entry[len(FILE_SCHEME) :]))
    return tuple(folders)
