"""Checkpoints of a training run: everything needed to continue it as if it had not stopped.

A checkpoint holds the model, the optimizer, the difficulty (the ``DifficultyTransform``'s
state), the frame/update/episode counters, the RNG states and the resolved config. It is
written to a temporary file and renamed over the previous one, so a kill at any moment leaves
either the old or the new checkpoint, never half of one. Loading refuses, with an error that
says what is wrong, a file that cannot be read, is not a checkpoint, or was written by a run
whose config differs in anything that shapes the training.
"""

from __future__ import annotations

import os
import random
from pathlib import Path
from typing import Any

import numpy as np
import torch

FORMAT_VERSION = 1
CHECKPOINT_NAME = "last.pt"
# Config sections that may change between a run and its resumption (budget, bookkeeping). Not
# ``collector``: its workers multiply the batch of an update and the pace of the difficulty, as
# ``env.num_envs`` does.
MAY_CHANGE = ("total_frames", "device", "threads", "checkpoint", "log", "out_dir", "run_name")


class CheckpointError(RuntimeError):
    """A checkpoint exists but cannot be used to resume this run."""


def rng_states() -> dict[str, Any]:
    return {"torch": torch.get_rng_state(), "numpy": np.random.get_state(), "python": random.getstate()}


def set_rng_states(states: dict[str, Any]) -> None:
    torch.set_rng_state(states["torch"])
    np.random.set_state(states["numpy"])
    random.setstate(states["python"])


def save_checkpoint(path: Path, state: dict[str, Any]) -> None:
    """Write ``state`` (plus the format version and RNG states) to ``path`` atomically."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    with open(tmp, "wb") as f:
        torch.save({"format": FORMAT_VERSION, "rng": rng_states(), **state}, f)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def config_differences(saved: dict[str, Any], current: dict[str, Any], prefix: str = "") -> list[str]:
    """The dotted keys whose values differ between two resolved configs (ignoring ``MAY_CHANGE``)."""
    diffs = []
    for key in sorted(set(saved) | set(current)):
        name = f"{prefix}{key}"
        if not prefix and key in MAY_CHANGE:
            continue
        a, b = saved.get(key, "<missing>"), current.get(key, "<missing>")
        if isinstance(a, dict) and isinstance(b, dict):
            diffs += config_differences(a, b, prefix=f"{name}.")
        elif a != b:
            diffs.append(f"{name}: {a!r} in the checkpoint, {b!r} now")
    return diffs


def load_checkpoint(path: Path, config: dict[str, Any]) -> dict[str, Any]:
    """Read the checkpoint at ``path`` and check that it belongs to a run with ``config``."""
    try:
        state = torch.load(path, map_location="cpu", weights_only=False)
    except Exception as error:
        raise CheckpointError(
            f"checkpoint {path} cannot be read ({type(error).__name__}: {error}); it is corrupt or "
            f"truncated. Move it away to start this run afresh, or restore a good copy."
        ) from error
    if not isinstance(state, dict) or state.get("format") != FORMAT_VERSION:
        found = state.get("format") if isinstance(state, dict) else type(state).__name__
        raise CheckpointError(
            f"{path} is not a gvgai-pcg training checkpoint of format {FORMAT_VERSION} (found {found!r})"
        )
    diffs = config_differences(state["config"], config)
    if diffs:
        raise CheckpointError(
            f"the run directory {path.parent.parent} holds a checkpoint of a run with a different config:\n  "
            + "\n  ".join(diffs)
            + "\nStart with the same settings to resume it, or choose another out_dir/run_name."
        )
    return state


def restore(
    state: dict[str, Any], model: torch.nn.Module, optimizer: torch.optim.Optimizer, difficulty
) -> None:
    """Load the saved model, optimizer, difficulty and RNG states into the live objects."""
    try:
        model.load_state_dict(state["model"])
        optimizer.load_state_dict(state["optimizer"])
        if difficulty is not None:
            difficulty.load_state_dict(state["difficulty"])
    except (RuntimeError, KeyError, ValueError) as error:
        raise CheckpointError(f"the checkpoint does not fit this run's model/optimizer: {error}") from error
    set_rng_states(state["rng"])
