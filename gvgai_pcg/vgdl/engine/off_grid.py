"""Sprites of a grid type off the grid's array: those a ``transformTo`` makes from a table sprite
that has walked off every level of the batch (Boulderdash: a butterfly a crab meets off an
unbordered level leaves its diamond out there, RULES.md §7.7).

No cell holds them, so each grid type a table transforms into has a table beside its grid,
``<type>_off`` (``x, y, alive``), with one slot per slot of the source table: a source sprite
transforms once (it is killed), so its slot is never reused. The kernels that read such a type
read both (``checks`` refuses the others): as a second of any rule (``Frame.overlap_count``), as
the first of ``collectResource`` (``resources``), in a termination's count and in the snapshot.
"""

from __future__ import annotations

import torch

from gvgai_pcg.games.geometry import overlaps, overlaps_aligned


def off_key(name: str) -> str:
    """The state entry of grid type ``name``'s sprites off the array."""
    return f"{name}_off"


def off_overlaps(
    values: dict[str, torch.Tensor],
    killed: torch.Tensor | None,
    x: torch.Tensor,
    y: torch.Tensor,
    aligned: bool,
) -> torch.Tensor:
    """``[B, N, K]``: rectangles at ``x, y`` (``[B, N]``) overlap off-array sprite k (present;
    not killed where ``killed`` is given)."""
    test = overlaps_aligned if aligned else overlaps
    present = values["alive"] if killed is None else values["alive"] & ~killed
    meets = test(x.unsqueeze(-1), y.unsqueeze(-1), values["x"].unsqueeze(-2), values["y"].unsqueeze(-2))
    return meets & present.unsqueeze(-2)


def put_off_grid(
    values: dict[str, torch.Tensor], where: torch.Tensor, x: torch.Tensor, y: torch.Tensor
) -> dict:
    """The off-array table with new sprites at ``x, y`` where ``where`` (all ``[B, K]``, by the
    source's slots)."""
    return {
        "x": torch.where(where, x, values["x"]),
        "y": torch.where(where, y, values["y"]),
        "alive": values["alive"] | where,
    }
