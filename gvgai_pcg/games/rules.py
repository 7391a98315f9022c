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
    aligned: bool = False,
) -> tuple[torch.Tensor, torch.Tensor]:
    """``A × A → stepBack`` within one entity table, in slot order (all ``[B, K]``).

    Sprite a (eligible where ``first``) goes back to ``last*`` iff, at its turn, it overlaps a
    sprite b ≠ a (present where ``second``) — where b < a is already at its final place and b > a
    still at its moved place. That recurrence is solved as a fixed point: iteration i settles
    at least slot i, and it stops as soon as nothing changes (usually after one or two rounds),
    so the result equals GVGAI's one-by-one processing without a loop over sprites.

    With ``aligned`` (every position a multiple of 10 in x and y, both now and last) two sprites
    overlap exactly when they share a position, so each sprite is compared by one number.
    """
    k = x.shape[-1]
    if k < 2:
        return x, y
    earlier = torch.ones(k, k, dtype=torch.bool, device=x.device).tril(-1)  # [a, b]: b < a
    candidates = second.unsqueeze(-2) & ~torch.eye(k, dtype=torch.bool, device=x.device)  # [B, a, b]
    if aligned:
        key, last_key = position_key(x, y), position_key(lastx, lasty)
        # b's place is its final one for b < a and its moved one otherwise; the latter part does not
        # change between rounds. Masks are combined with & and | (torch.where over [B, K, K] costs
        # several times more on the CPU).
        with_later = (key.unsqueeze(-1) == key.unsqueeze(-2)) & ~earlier & candidates
        earlier_candidates = earlier & candidates

        def hits(back: torch.Tensor) -> torch.Tensor:
            final = torch.where(back, last_key, key).unsqueeze(-2)
            return (key.unsqueeze(-1) == final) & earlier_candidates | with_later
    else:

        def hits(back: torch.Tensor) -> torch.Tensor:
            fx, fy = torch.where(back, lastx, x), torch.where(back, lasty, y)
            bx = torch.where(earlier, fx.unsqueeze(-2), x.unsqueeze(-2))  # [B, a, b]
            by = torch.where(earlier, fy.unsqueeze(-2), y.unsqueeze(-2))
            return overlaps(x.unsqueeze(-1), y.unsqueeze(-1), bx, by) & candidates

    back = torch.zeros_like(first)
    for _ in range(k):
        new_back = first & any_last(hits(back))
        if not torch.compiler.is_compiling() and torch.equal(new_back, back):
            break
        back = new_back
    return torch.where(back, lastx, x), torch.where(back, lasty, y)


def position_key(x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    """One int64 per position, equal exactly when both coordinates are (for |x| < 2^31)."""
    return (y.long() << 32) + x
