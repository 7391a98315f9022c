"""Tensors shared by every process of a run: buffers backed by memory-mapped files, and one lock
file that serialises their moves.

Collector workers receive a pickled copy of the env and of whatever state it reads, so a value
they all read and move (PPCG's difficulty, a curriculum's buffers) lives in files that every copy
maps. ``DifficultyTransform`` and the curricula's ``SharedState`` both share their buffers so.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

from filelock import FileLock
from torch import nn


def share_buffers_through(module: nn.Module, directory: Path) -> Path:
    """Back every buffer of ``module`` by a memory-mapped file in ``directory`` (from its current
    value); returns the lock file all processes lock around a move."""
    from tensordict import MemoryMappedTensor

    directory.mkdir(parents=True, exist_ok=True)
    for name, buffer in list(module.named_buffers()):
        path = directory / f"{name}.memmap"
        path.unlink(missing_ok=True)  # left by an earlier session of the run
        module.register_buffer(name, MemoryMappedTensor.from_tensor(buffer, filename=path))
    return directory / f"{type(module).__name__.lower()}.lock"


@contextlib.contextmanager
def exclusive(path: Path | None) -> Iterator[None]:
    """Hold an exclusive lock on the file ``path`` (nothing if ``None``)."""
    if path is None:
        yield
        return
    # Kept on release: a process already waiting holds the file open, and a new file at the same
    # path would let a third process in beside it. Forked workers each open their own lock.
    lock = FileLock(path, thread_local=False, fallback_to_soft=False, preserve_lock_file=True)
    with lock:
        yield
