"""Tensors shared by every process of a run: buffers backed by memory-mapped files, and one lock
file that serialises their moves.

Collector workers receive a pickled copy of the env and of whatever state it reads, so a value
they all read and move (PPCG's difficulty, a curriculum's buffers) lives in files that every copy
maps. ``DifficultyTransform`` and the curricula's ``SharedState`` both share their buffers so.
"""

from __future__ import annotations

import contextlib
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


def exclusive(path: Path | None) -> contextlib.AbstractContextManager[None]:
    """An exclusive lock on the file ``path`` for each ``with`` block (nothing if ``None``); the
    object can be kept and entered again."""
    return FileMutex(path) if path is not None else contextlib.nullcontext()


class FileMutex:
    """An exclusive lock on the file ``path`` around each ``with`` block; reusable and picklable,
    so a shared state keeps one from the moment it is shared."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._held: list[FileLock] = []  # at most one: the lock keeps every other holder out

    def __enter__(self) -> None:
        # A new FileLock per block, kept on release: a process already waiting holds the file
        # open, and a new file at the same path would let a third process in beside it. Forked
        # workers each open their own.
        lock = FileLock(self.path, thread_local=False, fallback_to_soft=False, preserve_lock_file=True)
        lock.acquire()
        self._held.append(lock)

    def __exit__(self, *exc_info: object) -> None:
        self._held.pop().release()

    def __getstate__(self) -> dict:
        return {"path": self.path, "_held": []}
