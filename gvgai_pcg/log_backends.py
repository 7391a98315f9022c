"""The log backends a run can mirror its rows to, and the extra each one needs installed.

Checked before anything of a run is written (the command line of ``gvgai-pcg train``, and again
when a session opens): a backend whose package is missing would otherwise fail at the logger's
creation, after the run's ``config.yaml`` and ``sessions.csv`` exist, with a long ImportError.
This module imports nothing heavy, so the command line is checked in a fraction of a second.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Iterable

# backend -> (the package it imports, the gvgai-pcg extra that installs it); csv needs nothing
BACKENDS: dict[str, tuple[str, str] | None] = {
    "csv": None,
    "tensorboard": ("tensorboard", "tensorboard"),
    "wandb": ("wandb", "wandb"),
}


def check_installed(names: Iterable[str]) -> None:
    """``ValueError`` (one line, naming the extra to install) for a backend whose package is not
    installed. An unknown name is left to the config's own check, which lists the valid ones."""
    for name in names:
        needs = BACKENDS.get(name)
        if needs is not None and importlib.util.find_spec(needs[0]) is None:
            raise ValueError(
                f"log.backends: {name} needs the {needs[0]} package, which is not installed; install it "
                f"with: pip install 'gvgai-pcg[{needs[1]}]' (or leave {name} out of log.backends)"
            )
