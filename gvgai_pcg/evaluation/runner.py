"""Play one episode on each of many levels at once, in one batched env.

Every env of the batch is given its own level (``LevelPerEnv``) and plays exactly one episode;
an env that finishes keeps being stepped with the others but is no longer recorded, so the
results are those of the first episode of each env.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import torch
from tensordict import TensorDictBase
from tqdm.auto import tqdm

from gvgai_pcg.envs import GVGAIEnv, LevelPerEnv
from gvgai_pcg.levels import Level

Policy = Callable[[TensorDictBase], torch.Tensor]


@dataclass
class EpisodeResults:
    """Per-episode outcomes, one entry per level played (``[N]`` each)."""

    scores: torch.Tensor
    lengths: torch.Tensor
    wins: torch.Tensor


def play_episodes(
    game: str,
    levels: Sequence[Level],
    policy: Policy,
    max_steps: int = 2000,
    seed: int = 0,
    obs: str = "tiles",
    device: torch.device | str = "cpu",
    progress: bool = True,
) -> EpisodeResults:
    """One episode per entry of ``levels`` (repeat a level to play it several times)."""
    env = GVGAIEnv(
        game,
        num_envs=len(levels),
        levels=LevelPerEnv(levels),
        obs=obs,
        max_steps=max_steps,
        device=device,
        seed=seed,
    )
    n = len(levels)
    scores = torch.zeros(n, device=env.device)
    lengths = torch.zeros(n, dtype=torch.int64, device=env.device)
    wins = torch.zeros(n, dtype=torch.bool, device=env.device)
    finished = torch.zeros(n, dtype=torch.bool, device=env.device)
    td = env.reset()
    bar = tqdm(total=max_steps, desc=f"{game}: {n} episodes", unit="step", disable=not progress, leave=False)
    for step in range(1, max_steps + 1):
        td.set("action", policy(td))
        td = env.step(td).get("next")
        done = td.get("done").squeeze(-1) & ~finished
        scores = torch.where(done, td.get("score").squeeze(-1), scores)
        lengths = torch.where(done, torch.full_like(lengths, step), lengths)
        wins = torch.where(done, td.get("won").squeeze(-1), wins)
        finished |= done
        bar.update(1)
        if bool(finished.all()):
            break
    bar.close()
    return EpisodeResults(scores.cpu(), lengths.cpu(), wins.cpu())
