"""Copying whole env rows between batched tensors and states, at close to memcpy speed.

Partial resets move rows around on every step in which an env finishes: fresh states out of a
bank, into the running state, observations into the running tensordict. PyTorch's CPU kernels for
this are uneven. ``index_select`` copies contiguous rows fast, but ``index_copy_`` walks byte
tensors element by element: 600 rows of Frogs' uint8 tiles take ~1 ms, the same rows seen as
int32 take 0.16 ms. So rows are copied through the widest integer view their size allows, and
rows that stay byte-sized (an odd number of bools) go through ``index_put_``, which is 2-6x
faster than ``index_copy_`` on bytes. TensorDict's own indexing (``td[index]``) costs about twice
a plain ``index_select`` per entry, so states are gathered entry by entry as well.
"""

from __future__ import annotations

from functools import cache

import torch
from tensordict import TensorDict

from gvgai_pcg._private_apis import unchecked_tensordict

_WIDE = ((torch.int64, 8), (torch.int32, 4), (torch.int16, 2))
# Copies of rows of at most SMALL_ROW_BYTES, or of fewer than SMALL_COPY_BYTES in all, go straight
# to index_copy_: viewing them costs more than it saves.
SMALL_ROW_BYTES = 8
SMALL_COPY_BYTES = 1 << 14


@cache
def _wide_dtype(dtype: torch.dtype, row_bytes: int) -> torch.dtype | None:
    """The widest integer type whose size divides ``row_bytes`` and exceeds ``dtype``'s, if any."""
    if row_bytes == 0 or dtype.is_floating_point or dtype.is_complex:
        return None
    size = dtype.itemsize
    return next((wide for wide, n in _WIDE if n > size and row_bytes % n == 0), None)


def wide_rows(tensor: torch.Tensor) -> torch.Tensor:
    """``tensor`` (``[N, ...]``, contiguous) as ``[N, M]`` of the widest integer type that divides
    its rows, sharing its memory (as ``[N, M]`` of its own type if none does)."""
    rows = tensor.shape[0]
    flat = tensor.view(rows, -1)
    wide = _wide_dtype(tensor.dtype, tensor.numel() // rows * tensor.element_size()) if rows else None
    if wide is None:
        return flat
    return (flat.view(torch.uint8) if tensor.dtype == torch.bool else flat).view(wide)


def copy_tensor_rows_(target: torch.Tensor, index: torch.Tensor, source: torch.Tensor) -> torch.Tensor:
    """``target[index] = source`` (rows along dim 0) through the fastest kernel; returns ``target``."""
    rows = target.shape[0]
    row_bytes = target.numel() // rows * target.element_size() if rows else 0
    if (
        row_bytes <= SMALL_ROW_BYTES
        or index.numel() * row_bytes < SMALL_COPY_BYTES
        or not (target.is_contiguous() and source.is_contiguous())
        or source.dtype != target.dtype
        or source.shape[1:] != target.shape[1:]
    ):
        target.index_copy_(0, index, source)
        return target
    wide_target, wide_source = wide_rows(target), wide_rows(source)
    if wide_target.element_size() == 1:
        wide_target.index_put_((index,), wide_source)
    else:
        wide_target.index_copy_(0, index, wide_source)
    return target


def copy_rows(target: TensorDict, source: TensorDict, index: torch.Tensor) -> None:
    """``target[index] = source``, entry by entry (several times cheaper than TensorDict's indexed
    assignment, which goes through ``index_put_`` on every entry)."""
    for key, value in source.items(True, True):
        copy_tensor_rows_(target.get(key), index, value)


def select_rows(state: TensorDict, index: torch.Tensor) -> TensorDict:
    """``state[index]`` for a 1-D ``index``: every entry gathered with ``index_select``, nested
    tables keeping their trailing batch dims."""
    values = {}
    for key, value in state.items():
        if isinstance(value, TensorDict):
            values[key] = select_rows(value, index)
        else:
            values[key] = value.index_select(0, index)
    # Built unchecked: every entry was just cut from a valid state (the checks cost a third more).
    batch_size = torch.Size([len(index), *state.batch_size[1:]])
    return unchecked_tensordict(values, batch_size, state.device)


def first_rows(state: TensorDict, count: int) -> TensorDict:
    """``state[:count]`` as views, entry by entry (TensorDict's own slicing costs several times
    more per entry)."""
    values = {}
    for key, value in state.items():
        values[key] = first_rows(value, count) if isinstance(value, TensorDict) else value[:count]
    return unchecked_tensordict(values, torch.Size([count, *state.batch_size[1:]]), state.device)
