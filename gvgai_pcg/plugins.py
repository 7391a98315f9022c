"""Plug-ins from installed packages' entry points, for every registry of the package (games,
curricula, learners): one loop, so that each kind refuses a wrong object and ignores a second
registration of a name in the same words.

It imports nothing of the package, so the lowest registry (games) can use it.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping
from importlib.metadata import entry_points
from typing import Any


def load_entry_points(
    group: str,
    kind: str,
    cls: type,
    registered: Mapping[str, Any],
    register: Callable[[Any], Any],
    same: Callable[[Any, Any], bool] = lambda a, b: a is b,
) -> None:
    """Register every entry point of ``group`` whose name ``registered`` lacks: it must load a
    ``cls`` with that ``name`` (``ValueError``). A name already registered keeps its object, with a
    warning where the entry point loads another one (``same`` says which are the same)."""
    for entry_point in entry_points(group=group):
        if entry_point.name in registered:
            if not same(registered[entry_point.name], entry_point.load()):
                warnings.warn(
                    f"{kind} plugin {entry_point.value!r} ignored: "
                    f"{entry_point.name!r} is already registered",
                    stacklevel=4,
                )
            continue
        loaded = entry_point.load()
        if not isinstance(loaded, cls) or loaded.name != entry_point.name:
            raise ValueError(
                f"{kind} plugin {entry_point.value!r}: the entry point {entry_point.name!r} must load the "
                f"{cls.__name__} of that name, got {loaded!r}"
            )
        register(loaded)
