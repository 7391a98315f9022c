"""Play one episode on each of many levels at once, in one batched env.

Every env of the batch is given its own level (``LevelPerEnv``) and plays exactly one episode;
an env that finishes keeps being stepped with the others but is no longer recorded, so the
results are those of the first episode of each env. The policy is asked only for the envs still
playing, so its cost follows the episodes left, not the batch.

What an evaluation costs was mostly not playing (docs/history/benchmarks-notebook.md, "Evaluation"):
on a shared CPU, torch's two intra-op threads wait on each other (the protocol on one Zelda run took
about 175 s of CPU with two threads and compiling, 13-14 s on one thread eagerly, at a load of 8-10
on 2 cores), and compiling the tick costs more than it saves in a job of 2,000 batched steps. So an
evaluation runs on one torch thread and ticks eagerly unless it can make
``COMPILE_PAYS_BACK_STEPS`` batched steps or more.

An episode's outcome depends only on the seed, its level and how many copies of that level come
before it, never on the rest of the batch: its env's seed is made from those three, and at every
step the runner hands each env a uniform number drawn from its own seed and the step
(``SAMPLE_KEY``), which the policies sample their actions with.
"""

from __future__ import annotations

import hashlib
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass

import torch
from tensordict import TensorDictBase

from gvgai_pcg.engine.step_plan import COMPILE_PAYS_BACK_STEPS, compile_pays_back  # noqa: F401 (re-exported)
from gvgai_pcg.envs import GVGAIEnv, LevelPerEnv
from gvgai_pcg.games.rng import derive_seeds, mix64, uniform
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.winnable import warn_unwinnable
from gvgai_pcg.progress import progress as progress_display

Policy = Callable[[TensorDictBase], torch.Tensor]
SAMPLE_KEY = "action_uniform"  # [B] float64 U[0, 1): the env's own random number for this step
STREAM_ACTIONS = 1
# Torch intra-op threads while playing: with two on a 2-core machine where other work holds a
# core, a step of 210 Zelda envs took 133-193 ms and the policy 155-248 ms, against 5-7 ms and
# 16-21 ms on one thread (load 9-11; docs/history/benchmarks-notebook.md, "Evaluation: the
# protocol on one run").
EVALUATION_THREADS = 1


def episode_seeds(levels: Sequence[Level], seed: int) -> torch.Tensor:
    """``[N]`` int64 env seeds: entry i's is a function of ``seed``, its level's content and how
    many equal levels come before it in ``levels``."""
    copies: Counter[Level] = Counter()
    keys = []
    for level in levels:
        digest = hashlib.blake2b(f"{level.game}\n{level}".encode(), digest_size=8).digest()
        keys.append((int.from_bytes(digest, "little", signed=True), copies[level]))
        copies[level] += 1
    content, repeat = torch.tensor(keys, dtype=torch.int64).reshape(-1, 2).unbind(-1)
    base = derive_seeds(seed, 1)
    return mix64(mix64(base ^ content) ^ repeat)


def sample_actions(probabilities: torch.Tensor, uniform_draws: torch.Tensor) -> torch.Tensor:
    """``[B]`` actions drawn from ``probabilities`` ``[B, A]`` by inverting their CDF at
    ``uniform_draws`` ``[B]``."""
    cdf = probabilities.to(torch.float64).cumsum(-1)
    below = (cdf < uniform_draws.to(cdf.device).unsqueeze(-1) * cdf[:, -1:]).sum(-1)
    return below.clamp(max=probabilities.shape[-1] - 1)


@contextmanager
def torch_threads(count: int) -> Iterator[None]:
    """Run the block on ``count`` torch intra-op threads, then restore the caller's setting."""
    before = torch.get_num_threads()
    torch.set_num_threads(count)
    try:
        yield
    finally:
        torch.set_num_threads(before)


def act(policy: Policy, td: TensorDictBase, finished: torch.Tensor, nil: torch.Tensor) -> torch.Tensor:
    """``[B]`` actions: the policy's for the envs still playing, asked of those rows alone (its
    cost follows the episodes left, not the batch), and NIL for the finished ones, whose steps
    are never recorded."""
    if not bool(finished.any()):
        return policy(td)
    playing = (~finished).nonzero().squeeze(-1)
    return nil.index_put((playing,), policy(td[playing]).to(nil.device, nil.dtype))


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
    label: str | None = None,
) -> EpisodeResults:
    """One episode per entry of ``levels`` (repeat a level to play it several times); a level
    that cannot be won is played all the same, with a warning (``gvgai_pcg.levels.winnable``).
    ``label`` names the agent in the progress line (``zelda-ppcg-seed0: 210 episodes``)."""
    warn_unwinnable(levels, "evaluation")
    env = GVGAIEnv(
        game,
        num_envs=len(levels),
        levels=LevelPerEnv(levels),
        obs=obs,
        max_steps=max_steps,
        device=device,
        seed=episode_seeds(levels, seed).tolist(),
        compile_tick=compile_pays_back(max_steps, device),
    )
    with torch_threads(EVALUATION_THREADS):
        return _play(env, policy, max_steps, progress, label)


def _play(
    env: GVGAIEnv, policy: Policy, max_steps: int, progress: bool, label: str | None = None
) -> EpisodeResults:
    """Step every env of ``env`` until each has finished its first episode (or ``max_steps``)."""
    game = env.game.name
    env_seeds = env.env_seeds
    n = env.num_envs
    scores = torch.zeros(n, device=env.device)
    lengths = torch.zeros(n, dtype=torch.int64, device=env.device)
    wins = torch.zeros(n, dtype=torch.bool, device=env.device)
    finished = torch.zeros(n, dtype=torch.bool, device=env.device)
    td = env.reset()
    bar = progress_display(max_steps, f"{label or game}: {n} episodes", "step", enabled=progress, leave=False)
    nil = torch.zeros(n, dtype=torch.int64, device=env.device)
    for step in range(1, max_steps + 1):
        draws = uniform(env_seeds, torch.full_like(env_seeds, step), 0, STREAM_ACTIONS)
        td.set(SAMPLE_KEY, draws.to(env.device))
        td.set("action", act(policy, td, finished, nil))
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
