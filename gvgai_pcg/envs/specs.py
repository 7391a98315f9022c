"""The TorchRL specs of a ``GVGAIEnv``: what its observations, actions, rewards and dones are."""

from __future__ import annotations

import torch
from torchrl.data import Bounded, Categorical, Composite, Unbounded

from gvgai_pcg.games.base import Game
from gvgai_pcg.games.geometry import CELL


def env_specs(
    game: Game, obs: str, num_envs: int, device: torch.device
) -> dict[str, Composite | Categorical]:
    """The ``observation_spec``, ``action_spec``, ``reward_spec`` and ``done_spec`` of ``num_envs``
    envs of ``game`` observing ``obs`` on ``device``.

    Both observation specs are uint8 Unbounded. Not Bounded: TorchRL builds a Bounded's low and
    high at full size and compares them element by element when it takes the batch size (4,096
    envs: 1.4 s for tiles, 30 s for pixels). Nor Binary for the 0/1 tiles: TorchRL's transforms
    leave a Binary as it is, so after a cast to float ObservationNorm and VecNorm produce values
    it refuses (check_env_specs fails); an Unbounded they take as it comes."""
    b, h, w = num_envs, game.level_format.height, game.level_format.width
    shape = (b, len(game.tile_types), h, w) if obs == "tiles" else (b, 3, h * CELL, w * CELL)

    def flag() -> Categorical:
        return Categorical(2, shape=(b, 1), dtype=torch.bool, device=device)

    def difficulty() -> Bounded:
        return Bounded(0.0, 1.0, shape=(b, 1), dtype=torch.float64, device=device)

    observation = {
        obs: Unbounded(shape=shape, dtype=torch.uint8, device=device),
        "score": Unbounded(shape=(b, 1), dtype=torch.float32, device=device),
        "won": flag(),
        "difficulty": difficulty(),
        "level_seed": Unbounded(shape=(b, 1), dtype=torch.int64, device=device),
        "level_difficulty": difficulty(),
    }
    return {
        "observation_spec": Composite(observation, shape=(b,)),
        "action_spec": Categorical(game.num_actions, shape=(b,), dtype=torch.int64, device=device),
        "reward_spec": Unbounded(shape=(b, 1), dtype=torch.float32, device=device),
        "done_spec": Composite({key: flag() for key in ("done", "terminated", "truncated")}, shape=(b,)),
    }
