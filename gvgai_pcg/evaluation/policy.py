"""A trained actor-critic as a policy: the one way to load ``model.pt`` or a checkpoint and act.

The evaluator, the replays, ``evaluate`` and your own scripts all go through ``load_policy``:
it reads the file as tensors and plain data only, refuses non-finite (diverged) weights, rebuilds
the network from the config saved with it (or the run's), and wraps it as a policy
``tensordict -> action [B]``. Actions are sampled from the softmax with the evaluation runner's
per-env uniform draws (``SAMPLE_KEY``) where the tensordict has them, so an evaluation does not
depend on the batch; else from the policy's own seeded generator, or the argmax when ``greedy``.
"""

from __future__ import annotations

import re
from pathlib import Path

import torch
from tensordict import TensorDictBase

from gvgai_pcg.evaluation.checkpoints import RunInfo, load_state
from gvgai_pcg.evaluation.runner import SAMPLE_KEY, sample_actions
from gvgai_pcg.games import get_game
from gvgai_pcg.games.geometry import observation_shape
from gvgai_pcg.rl.models import ActorCritic, make_actor_critic
from gvgai_pcg.rundir.checkpoint import CheckpointError


def policy_actions(
    net: ActorCritic, tensordict: TensorDictBase, obs_key: str, greedy: bool, generator: torch.Generator
) -> torch.Tensor:
    """``[B]`` actions of an actor-critic on the observation ``obs_key``."""
    logits, _ = net(tensordict.get(obs_key))
    if greedy:
        return logits.argmax(-1)
    probabilities = logits.float().softmax(-1)
    draws = tensordict.get(SAMPLE_KEY, None)
    if draws is not None:
        return sample_actions(probabilities, draws)
    return torch.multinomial(probabilities, 1, generator=generator).squeeze(-1)


class ActorCriticPolicy:
    """The trained network as a policy: ``tensordict`` with the observation -> ``action [B]``."""

    def __init__(
        self, net: torch.nn.Module, obs_key: str, greedy: bool = False, seed: int = 0, device: str = "cpu"
    ) -> None:
        self.net = net.to(device).eval()
        self.obs_key, self.greedy = obs_key, greedy
        self.generator = torch.Generator(device=device).manual_seed(seed)

    @torch.no_grad()
    def __call__(self, tensordict: TensorDictBase) -> torch.Tensor:
        return policy_actions(self.net, tensordict, self.obs_key, self.greedy, self.generator)


def load_policy(
    source: RunInfo | Path | str, greedy: bool = False, seed: int = 0, device: str = "cpu"
) -> ActorCriticPolicy:
    """The policy of a run (``RunInfo``: its config, the checkpoint it names) or of one model or
    checkpoint file (its own saved config), on ``device``."""
    path = Path(source) if isinstance(source, str | Path) else source.model_file
    state = load_state(path)  # tensors and plain data only, finite weights
    config = state["config"] if isinstance(source, str | Path) else source.config
    game, obs, model = config["game"]["name"], config["env"]["obs"], config["model"]
    net = make_actor_critic(
        model["name"], obs, observation_shape(game, obs), get_game(game).num_actions, model["hidden"]
    )
    try:
        net.load_state_dict(state["model"])
    except RuntimeError as error:  # a size mismatch: the file's weights are not of this network
        raise CheckpointError(
            f"{path}: its weights do not fit the run's network ({_first_mismatch(error)})"
        ) from None
    return ActorCriticPolicy(net, obs, greedy=greedy, seed=seed, device=device)


def _first_mismatch(error: RuntimeError) -> str:
    """``size mismatch for torso.0.weight: [32, 9, 3, 3] in the file, [16, 9, 3, 3] in the network
    (and 9 more)``, from torch's list of every mismatched entry."""
    text = " ".join(str(error).split())
    found = re.findall(
        r"size mismatch for ([\w.]+): copying a param with shape torch\.Size\((\[[^\]]*\])\) from "
        r"checkpoint, the shape in current model is torch\.Size\((\[[^\]]*\])\)",
        text,
    )
    if not found:
        return text[:300]
    name, saved, current = found[0]
    more = f" (and {len(found) - 1} more)" if len(found) > 1 else ""
    return f"size mismatch for {name}: {saved} in the file, {current} in the network{more}"
