"""How much memory a training config needs at least, so that ``env.num_envs=1000000`` is refused in
one line before the run starts, not by an allocation error minutes into it.

The estimate is a lower bound per env: its observations (uint8: the env's current and next one,
and the rollout's ``n_steps``) and the model's activations for the frames of one backward pass
(``n_steps`` per env, split into ``minibatches`` where the learner has them), measured by one
forward pass of the real model on a single observation. The engine's own state and the optimiser
come on top, so a config refused here could not have run.
"""

from __future__ import annotations

import os
from typing import Any

from gvgai_pcg.games import get_game
from gvgai_pcg.games.geometry import observation_shape
from gvgai_pcg.rl.models import make_actor_critic

# Below this many envs a run is never checked: it fits any machine that runs the package, and the
# check would import torch into the config check of every command line.
CHECKED_FROM_ENVS = 4096


def available_bytes() -> int | None:
    """The memory the system can give a new process now (Linux's MemAvailable), ``None`` where unknown."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def bytes_per_env(config: dict[str, Any]) -> int:
    """The least memory one env of ``config`` takes in training (see the module docstring)."""
    import torch

    game, obs = config["game"]["name"], config["env"]["obs"]
    shape = observation_shape(game, obs)
    model = config["model"]
    net = make_actor_critic(model["name"], obs, shape, get_game(game).num_actions, int(model["hidden"]))
    activations = 0

    def count(module, inputs, output) -> None:
        nonlocal activations
        if isinstance(output, torch.Tensor) and not isinstance(module, torch.nn.Flatten):
            activations += output.numel() * output.element_size()

    hooks = [m.register_forward_hook(count) for m in net.modules() if not list(m.children())]
    with torch.no_grad():
        net(torch.zeros(1, *shape, dtype=torch.uint8))
    for hook in hooks:
        hook.remove()
    observation = shape[0] * shape[1] * shape[2]
    n_steps = int(config["algo"].get("n_steps", 1))
    minibatches = max(1, int(config["algo"].get("minibatches", 1)))
    return observation * (n_steps + 2) + (activations + 4 * observation) * n_steps // minibatches


def check_memory(config: dict[str, Any], key: str = "env.num_envs") -> None:
    """``ValueError`` naming ``key`` when the config's envs need more memory than is available."""
    envs = int(config["env"]["num_envs"]) * int(config.get("collector", {}).get("workers", 1))
    if envs < CHECKED_FROM_ENVS or not str(config.get("device", "cpu")).startswith("cpu"):
        return
    available = available_bytes()
    if available is None:
        return
    per_env = bytes_per_env(config)
    needed = envs * per_env
    if needed > available:
        fit = available // per_env // max(1, envs // int(config["env"]["num_envs"]))
        raise ValueError(
            f"{key}={config['env']['num_envs']}: the run needs at least {_size(needed)} of memory "
            f"({_size(per_env)} per env: its observations, the rollout and the model's activations), "
            f"more than the {_size(available)} available; lower {key} (about {fit} fit)"
        )


def _size(count: int) -> str:
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if count >= scale:
            return f"{count / scale:.1f} {unit}"
    return f"{count} bytes"
