"""Small constant lookup tables (per-kind, per-action, per-direction constants), one way for
every game.

A rule that needs a constant per sprite kind or per action writes ``lookup(VALUES, codes)`` with
``VALUES`` the plain Python tuple it declares next to its other constants. The tensor behind it is
made once per (values, dtype, device) and read with ``index_select``, which is several times
cheaper than advanced indexing (``table[codes]``) on the CPU; no eager tick builds a table (a
compiled one holds it as a constant of its graph).
"""

from __future__ import annotations

from functools import cache

import torch


@cache
def constant_table(values: tuple, dtype: torch.dtype, device: torch.device) -> torch.Tensor:
    """``torch.tensor(values)`` of ``dtype`` on ``device``, made once and shared: never write to it."""
    return torch.tensor(values, dtype=dtype, device=device)


def pick(table: torch.Tensor, codes: torch.Tensor) -> torch.Tensor:
    """``table[codes]`` for a 1-D lookup table and integer codes of any shape, by ``index_select``."""
    return table.index_select(0, codes.reshape(-1)).view(codes.shape)


def lookup(values: tuple, codes: torch.Tensor, dtype: torch.dtype = torch.int64) -> torch.Tensor:
    """``values[codes]`` elementwise, as a tensor of ``dtype`` on ``codes``' device (codes: any shape)."""
    if torch.compiler.is_compiling():  # a constant of the graph; the cache serves eager ticks
        return pick(torch.tensor(values, dtype=dtype, device=codes.device), codes)
    return pick(constant_table(values, dtype, codes.device), codes)
