"""Effects shared by several games whose GVGAI semantics are sequential.

GVGAI applies a rule to the first sprites one at a time, and an earlier application (a
stepBack) is visible to later ones. Where that order matters, the functions here reproduce it
exactly with batched tensor ops.
"""

from __future__ import annotations

import torch

from gvgai_pcg.games.geometry import any_last, overlaps


def step_back_in_order(
    x: torch.Tensor,
    y: torch.Tensor,
    lastx: torch.Tensor,
    lasty: torch.Tensor,
    first: torch.Tensor,
    second: torch.Tensor,
) -> tuple[torch.Tensor, torch.Tensor]:
    """``A × A → stepBack`` within one entity table, in slot order (all ``[B, K]``).

    Sprite a (eligible where ``first``) goes back to ``last*`` iff, at its turn, it overlaps a
    sprite b ≠ a (present where ``second``) — where b < a is already at its final place and b > a
    still at its moved place. That recurrence is solved as a fixed point: iteration i settles
    at least slot i, and it stops as soon as nothing changes (usually after one or two rounds),
    so the result equals GVGAI's one-by-one processing without a loop over sprites.
    """
    k = x.shape[-1]
    if k < 2:
        return x, y
    earlier = torch.ones(k, k, dtype=torch.bool, device=x.device).tril(-1)  # [a, b]: b < a
    other = ~torch.eye(k, dtype=torch.bool, device=x.device)
    back = torch.zeros_like(first)
    for _ in range(k):
        fx, fy = torch.where(back, lastx, x), torch.where(back, lasty, y)
        bx = torch.where(earlier, fx.unsqueeze(-2), x.unsqueeze(-2))  # [B, a, b]
        by = torch.where(earlier, fy.unsqueeze(-2), y.unsqueeze(-2))
        hit = overlaps(x.unsqueeze(-1), y.unsqueeze(-1), bx, by) & second.unsqueeze(-2) & other
        new_back = first & any_last(hit)
        if torch.equal(new_back, back):
            break
        back = new_back
    return torch.where(back, lastx, x), torch.where(back, lasty, y)
