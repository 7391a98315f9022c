"""Training throughput: end-to-end frames/s against the model's own forward+backward limit.

``python -m gvgai_pcg.rl.benchmark [hydra overrides]`` trains a short run of the given config
(default: the fast default, PPCG on Zelda) and then times the same network's forward+backward
alone on identical batches (``num_envs x n_steps`` observations taken from the env), the upper
bound for an A2C step. Steady state only: the first batch (warm-up) is left out of both.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

import torch
from omegaconf import DictConfig

from gvgai_pcg.rl.a2c import train
from gvgai_pcg.rl.environment import EnvFactory, make_difficulty
from gvgai_pcg.rl.models import make_actor_critic


def model_limit_fps(cfg: DictConfig, seconds: float = 5.0) -> tuple[float, float]:
    """Frames/s of forward+backward (the A2C loss's work) on one batch of real observations,
    per second of wall time and per second of CPU time."""
    if cfg.threads:
        torch.set_num_threads(int(cfg.threads))
    env = EnvFactory(
        cfg.game.name,
        cfg.regimen,
        int(cfg.env.num_envs),
        cfg.env.obs,
        int(cfg.env.max_steps),
        cfg.device,
        int(cfg.seed),
        make_difficulty(cfg.regimen, cfg.game.name),
    )()
    obs_key, n_steps = cfg.env.obs, int(cfg.algo.n_steps)
    td = env.reset()
    frames = [td.get(obs_key)]
    for _ in range(n_steps - 1):
        td = env.rand_step(td)
        td = env.step_mdp(td)
        frames.append(td.get(obs_key))
    batch = torch.cat(frames)  # [num_envs * n_steps, C, H, W]
    net = make_actor_critic(
        cfg.model.name, obs_key, tuple(batch.shape[1:]), env.action_spec.space.n, int(cfg.model.hidden)
    ).to(cfg.device)
    optimizer = torch.optim.RMSprop(net.parameters(), lr=float(cfg.algo.lr))

    def update() -> None:
        logits, value = net(batch)
        loss = logits.logsumexp(-1).mean() + value.pow(2).mean()
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()

    update()  # warm-up
    count, start, cpu = 0, time.perf_counter(), time.process_time()
    while time.perf_counter() - start < seconds:
        update()
        count += 1
    frames = count * batch.shape[0]
    return frames / (time.perf_counter() - start), frames / (time.process_time() - cpu)


def benchmark(cfg: DictConfig) -> dict[str, float]:
    """End-to-end and model-only frames/s for ``cfg``, per wall and per CPU second, and their ratios."""
    with tempfile.TemporaryDirectory() as tmp:
        result = train(cfg, Path(tmp) / "run")
    limit, cpu_limit = model_limit_fps(cfg)
    return {
        "end_to_end_fps": result.fps,
        "model_limit_fps": limit,
        "ratio": result.fps / limit,
        "end_to_end_cpu_fps": result.cpu_fps,
        "model_limit_cpu_fps": cpu_limit,
        "cpu_ratio": result.cpu_fps / cpu_limit,
        "frames_per_batch": int(cfg.env.num_envs) * int(cfg.algo.n_steps),
        "load": os.getloadavg()[0],
    }


def main(argv: list[str]) -> int:
    if {"-h", "--help"} & set(argv):
        print(__doc__.strip())
        return 0
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir

    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        cfg = compose("config", overrides=["log.curve=false", "log.backends=[]", *argv])
    numbers = benchmark(cfg)
    print(
        f"{cfg.run_name}: end-to-end {numbers['end_to_end_fps']:.0f} frames/s, model fwd+bwd limit "
        f"{numbers['model_limit_fps']:.0f} frames/s ({numbers['ratio']:.0%}), batch "
        f"{numbers['frames_per_batch']} frames, load {numbers['load']:.1f}\n"
        f"  per CPU second: end-to-end {numbers['end_to_end_cpu_fps']:.0f}, model "
        f"{numbers['model_limit_cpu_fps']:.0f} ({numbers['cpu_ratio']:.0%})"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
