"""Imports torchrl without its one change to global state, for the Gymnasium entry points.

On import, torchrl sets multiprocessing's start method to "spawn" where none was set. A script
that only uses the Gymnasium ids then gets "spawn" for ``gymnasium.make_vec(...,
vectorization_mode="async")`` and its own pools, and, without an ``if __name__ == "__main__"``
guard, crashes as each worker re-runs the script. TorchRL does not need the global setting: its
collectors and batched envs take a context of their own (``torchrl._utils._get_mp_ctx``: "spawn"
unless the user set a method). So the setting is undone here when torchrl made it; a method
that the user set before is left as it is.
"""

from __future__ import annotations

import multiprocessing
import sys


def import_torchrl() -> None:
    """Import torchrl, leaving multiprocessing's start method as it was (unset, or the user's)."""
    if "torchrl" in sys.modules:
        return
    before = multiprocessing.get_start_method(allow_none=True)
    import torchrl  # noqa: F401

    if before is None and multiprocessing.get_start_method(allow_none=True) is not None:
        multiprocessing.set_start_method(None, force=True)


import_torchrl()
