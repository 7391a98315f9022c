"""A stepBack among the sprites of one table, in slot order, for a table whose sprites stay on
whole cells along at least one axis (Boulderdash's boulders keep their column, falling 2 px a
tick).

Sprite a goes back iff, at its turn, it overlaps a present b != a, where b < a is at its final
place and b > a at its moved place (``games.rules.step_back_in_order``, which compares every pair
by both coordinates each round). Here each place is one number, the aligned coordinate times
``KEY_AXIS`` plus the other: two places overlap exactly when their numbers differ by less than a
cell, so a pair costs one subtraction, and the pairs are compared once, before the rounds (each
round then combines bool masks). Eagerly on the CPU (``frame.reads_back``), only the sprites
near another (within a cell, at its moved or last place: ``near``) take part, gathered in slot
order: a sprite near none is never stepped back and steps back none.
"""

from __future__ import annotations

import torch

from gvgai_pcg.games.geometry import CELL, any_last
from gvgai_pcg.vgdl.engine.frame import reads_back

KEY_AXIS = 1 << 32  # aligned coordinate * KEY_AXIS + the other (|coordinates| < 2^31)
FAR = 1 << 62  # an absent sprite's place: far from every place and from each other's
FAR_SLOT = 1 << 20


def ordered_step_back(
    x: torch.Tensor,
    y: torch.Tensor,
    lastx: torch.Tensor,
    lasty: torch.Tensor,
    first: torch.Tensor,
    second: torch.Tensor,
    aligned_x: bool,
) -> tuple[torch.Tensor, torch.Tensor]:
    """New ``x, y`` (all ``[B, K]``) after the stepBack; ``first``: the sprites that may step back,
    ``second``: those present; ``aligned_x``: x is on whole cells (else y is)."""
    major, minor, last_major, last_minor = (x, y, lastx, lasty) if aligned_x else (y, x, lasty, lastx)
    key, last = major * KEY_AXIS + minor, last_major * KEY_AXIS + last_minor
    if not reads_back(key):
        back = _resolve(key, last, first, second)
    else:
        near = _near(key, last, second)
        count = int(near.sum(-1).max()) if near.numel() else 0
        if count == 0:
            return x, y
        # the near ones, in slot order
        slots = (~near).to(torch.int8).sort(dim=-1, stable=True).indices[:, :count]

        def gather(values: torch.Tensor) -> torch.Tensor:
            return torch.gather(values, 1, slots)

        valid = gather(near)
        chosen = _resolve(gather(key), gather(last), gather(first) & valid, gather(second) & valid)
        back = torch.zeros_like(first).scatter(1, slots, chosen)
    return torch.where(back, lastx, x), torch.where(back, lasty, y)


def _near(key: torch.Tensor, last: torch.Tensor, present: torch.Tensor) -> torch.Tensor:
    """``[B, K]``: present sprites within a cell of another present sprite's place, comparing
    moved with moved, moved with last and last with moved (by sorting, not pairwise)."""
    spread = torch.arange(key.shape[-1], device=key.device) * FAR_SLOT + FAR
    key = torch.where(present, key, spread)
    last = torch.where(present, last, spread + FAR_SLOT // 2)
    keys, lasts = key.sort(-1).values, last.sort(-1).values

    def within(values: torch.Tensor, around: torch.Tensor) -> torch.Tensor:
        return torch.searchsorted(values, around + CELL) - torch.searchsorted(values, around - (CELL - 1))

    own = ((key - last).abs() < CELL).long()  # a sprite's last place near its own moved one
    near = (within(keys, key) > 1) | (within(lasts, key) > own) | (within(keys, last) > own)
    return near & present


def _resolve(
    key: torch.Tensor, last: torch.Tensor, first: torch.Tensor, second: torch.Tensor
) -> torch.Tensor:
    """Which sprites step back (``[B, K]``), as a fixed point over the slot order (see the
    module docstring); it stops eagerly once a round changes nothing."""
    k = key.shape[-1]
    earlier = torch.ones(k, k, dtype=torch.bool, device=key.device).tril(-1)  # [a, b]: b < a
    candidates = second.unsqueeze(-2) & ~torch.eye(k, dtype=torch.bool, device=key.device)
    meets_moved = ((key.unsqueeze(-1) - key.unsqueeze(-2)).abs() < CELL) & candidates
    meets_last = ((key.unsqueeze(-1) - last.unsqueeze(-2)).abs() < CELL) & candidates & earlier
    later = any_last(meets_moved & ~earlier)  # b > a is where it moved, whatever happens
    meets_earlier = meets_moved & earlier
    back = torch.zeros_like(first)
    for _ in range(k):
        went = back.unsqueeze(-2)
        new_back = first & (later | any_last(meets_earlier & ~went) | any_last(meets_last & went))
        if not torch.compiler.is_compiling() and torch.equal(new_back, back):
            break
        back = new_back
    return back
