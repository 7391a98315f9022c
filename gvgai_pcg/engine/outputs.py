"""What a step tells the agent besides its observation: the score, whether the game was won,
and how the episode ended (RULES.md §1.8: a win or a loss terminates, the step limit truncates).

One function for the eager env and for the compiled step, which computes these in the same graph
as the tick (``gvgai_pcg.engine.compiled``): eagerly they are a dozen small ops a step, a sixth
of a step of 64 Zelda envs.
"""

from __future__ import annotations

import torch
from tensordict import TensorDict


def episode_outputs(
    state: TensorDict,
    steps: torch.Tensor,
    max_steps: int,
    running: torch.Tensor | None = None,
    score_before: torch.Tensor | None = None,
) -> dict[str, torch.Tensor]:
    """``score`` (float32), ``won``, ``terminated``, ``truncated`` and ``done``, each ``[B, 1]``, of
    ``state`` after ``steps`` steps of at most ``max_steps``, and, after a step from a score of
    ``score_before``, the ``reward`` (float32). Envs where ``running`` (``[B]`` bool, if given) is
    false have just been reset and are not done (a Frogs level without goals is won at its reset
    tick, but its episode only ends at the next step)."""
    won = state.get("won")
    terminated = won | state.get("lost")
    truncated = steps >= max_steps
    if running is not None:
        terminated = terminated & running
        truncated = truncated & running
    truncated = truncated & ~terminated
    score = state.get("score")
    outputs = {
        "score": score.to(torch.float32).unsqueeze(-1),
        "won": won.unsqueeze(-1).clone(),
        "terminated": terminated.unsqueeze(-1),
        "truncated": truncated.unsqueeze(-1),
        "done": (terminated | truncated).unsqueeze(-1),
    }
    if score_before is not None:
        outputs["reward"] = (score - score_before).to(torch.float32).unsqueeze(-1)
    return outputs
