"""Large CPU output buffers, reused once nothing outside the pool refers to them.

Every step allocates an observation (14 MB of tiles for 4,096 Frogs envs) and a step that resets
envs copies it once more. glibc hands such sizes back to the kernel when they are freed, so each
new buffer page-faults on first touch (about 3,500 faults for 14 MB), which costs more than
writing it. A pool keeps the last few buffers and hands one out again only when its storage has
no user left but the pool: the tensors given out are views, each holding a reference to the
storage, so a buffer still held anywhere (a rollout, a numpy array, a replay buffer, its storage
object) is never overwritten, nor is one that was moved to shared memory (sent to another
process). CUDA has its own caching allocator, so off the CPU the pool just allocates.
"""

from __future__ import annotations

import sys

import torch

from gvgai_pcg._private_apis import HAS_STORAGE_USE_COUNT, storage_use_count


def _references(buffer: torch.Tensor) -> tuple[int, int]:
    """What refers to ``buffer``'s storage: tensors (and arrays) through its use count, and
    holders of its Python storage object (``t.untyped_storage()``, which PyTorch keeps once per
    storage and so adds nothing to the use count) through that object's reference count."""
    storage = buffer.untyped_storage()
    return storage_use_count(storage), sys.getrefcount(storage)


class BufferPool:
    """Up to ``keep`` flat buffers of ``min_bytes`` to ``max_bytes`` each; :meth:`empty` returns a
    view of a free one of the asked size and type, or of a new one. Smaller requests are not
    pooled (they cost little and would push the large buffers out), nor are larger ones (the
    pool would hold on to too much memory: pixel observations of 4,096 envs take 0.4 GB)."""

    def __init__(self, keep: int = 4, min_bytes: int = 1 << 16, max_bytes: int = 1 << 25) -> None:
        self.keep, self.min_bytes, self.max_bytes = keep, min_bytes, max_bytes
        self._buffers: list[tuple[torch.Tensor, tuple[int, int]]] = []  # (buffer, references when unused)

    def empty(self, numel: int, dtype: torch.dtype, device: torch.device | str) -> torch.Tensor:
        """A flat tensor of ``numel`` elements with arbitrary contents."""
        device = torch.device(device)
        size = numel * dtype.itemsize
        pooled = self.min_bytes <= size <= self.max_bytes
        if not pooled or device.type != "cpu" or not HAS_STORAGE_USE_COUNT:
            return torch.empty(numel, dtype=dtype, device=device)
        # A buffer moved to shared memory (sent to another process) may be read there at any time.
        self._buffers = [entry for entry in self._buffers if not entry[0].untyped_storage().is_shared()]
        for position, (buffer, unused) in enumerate(self._buffers):
            if buffer.numel() == numel and buffer.dtype == dtype and _references(buffer) == unused:
                self._buffers.append(self._buffers.pop(position))  # most recently used last
                return buffer[:]
        buffer = torch.empty(numel, dtype=dtype, device=device)
        self._buffers.append((buffer, _references(buffer)))
        if len(self._buffers) > self.keep:
            self._buffers.pop(0)
        return buffer[:]

    def clone(self, tensor: torch.Tensor) -> torch.Tensor:
        """A contiguous copy of ``tensor`` in a pooled buffer."""
        copy = self.empty(tensor.numel(), tensor.dtype, tensor.device).view(tensor.shape)
        return copy.copy_(tensor)

    def __len__(self) -> int:
        return len(self._buffers)
