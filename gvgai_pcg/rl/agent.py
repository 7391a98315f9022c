"""A trained agent as a policy for the evaluation runner: ``model.pt`` in, actions out."""

from __future__ import annotations

from pathlib import Path

import torch
from tensordict import TensorDictBase

from gvgai_pcg.evaluation.runner import SAMPLE_KEY, sample_actions
from gvgai_pcg.games import get_game
from gvgai_pcg.games.geometry import CELL
from gvgai_pcg.levels import level_format
from gvgai_pcg.rl.checkpoint import check_finite, read_file
from gvgai_pcg.rl.models import ActorCritic, make_actor_critic


def policy_actions(
    net: ActorCritic, tensordict: TensorDictBase, obs_key: str, greedy: bool, generator: torch.Generator
) -> torch.Tensor:
    """``[B]`` actions of an actor-critic on the observation ``obs_key``: the argmax, or sampled
    from its softmax, with the evaluation runner's per-env uniform draws (``SAMPLE_KEY``) where
    the tensordict has them, else with ``generator``."""
    logits, _ = net(tensordict.get(obs_key))
    if greedy:
        return logits.argmax(-1)
    probabilities = logits.float().softmax(-1)
    draws = tensordict.get(SAMPLE_KEY, None)
    if draws is not None:
        return sample_actions(probabilities, draws)
    return torch.multinomial(probabilities, 1, generator=generator).squeeze(-1)


class TrainedAgent:
    """Samples actions from a trained actor-critic (``greedy=True``: the most likely action).

    Args:
        path: a run's ``model.pt`` (or ``checkpoints/last.pt``); refused when crafted (it would
            have to run code to load) or diverged (non-finite weights).
        seed: seeds the sampling generator.
    """

    def __init__(self, path: Path | str, seed: int = 0, greedy: bool = False, device: str = "cpu") -> None:
        saved = read_file(Path(path))  # tensors and plain data only
        check_finite(saved, Path(path))
        config = saved["config"]
        game = get_game(config["game"]["name"])
        self.obs_key = config["env"]["obs"]
        fmt = level_format(game.name)
        shape = (
            (len(game.tile_types), fmt.height, fmt.width)
            if self.obs_key == "tiles"
            else (3, fmt.height * CELL, fmt.width * CELL)
        )
        self.net: ActorCritic = make_actor_critic(
            config["model"]["name"], self.obs_key, shape, game.num_actions, config["model"]["hidden"]
        ).to(device)
        self.net.load_state_dict(saved["model"])
        self.net.eval()
        self.greedy = greedy
        self.generator = torch.Generator(device=device).manual_seed(seed)

    @torch.no_grad()
    def __call__(self, tensordict: TensorDictBase) -> torch.Tensor:
        return policy_actions(self.net, tensordict, self.obs_key, self.greedy, self.generator)
