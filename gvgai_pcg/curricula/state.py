"""Curriculum state shared by every env and collector worker of a run, and kept in checkpoints.

A curriculum's state (``Curriculum.make_state``) is read by the level sources of every env and
moved by ``observe`` (or, for PPCG, by its transform). ``SharedState`` gives a plug-in what
``DifficultyTransform`` has for PPCG's d: tensors registered as buffers (``register_shared``) live
in shared memory, so in-process envs see one value; ``share_through(directory)`` backs them by
memory-mapped files, so collector worker processes, which receive a pickled copy, read and
move the very same values; ``with state.lock:`` serialises the moves of all processes; and
``state_dict`` / ``load_state_dict`` carry them into checkpoints and back.
"""

from __future__ import annotations

import contextlib
import math
from pathlib import Path

import torch
from torch import nn

from gvgai_pcg.envs.shared_buffers import exclusive, share_buffers_through


class SharedState(nn.Module):
    """Base of a curriculum's shared state: register tensors with ``register_shared``, move them
    inside ``with self.lock:``."""

    def __init__(self) -> None:
        super().__init__()
        self.lock_path: Path | None = None
        # Decided when the state is shared, so that a move pays no call to find its lock.
        self.lock: contextlib.AbstractContextManager[None] = contextlib.nullcontext()

    def register_shared(self, name: str, value: torch.Tensor) -> torch.Tensor:
        """Keep ``value`` as the shared buffer ``name`` (in shared memory) and return it."""
        self.register_buffer(name, value.clone().share_memory_())
        return getattr(self, name)

    def share_through(self, directory: Path) -> None:
        """Share the buffers with worker processes through files in ``directory``."""
        self.lock_path = share_buffers_through(self, directory)
        self.lock = exclusive(self.lock_path)

    @property
    def difficulty(self) -> float:
        """The difficulty a training log shows for the curriculum (NaN: none)."""
        return math.nan
