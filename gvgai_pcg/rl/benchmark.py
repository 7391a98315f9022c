"""Training throughput: end-to-end frames/s against the network's own limit.

``python -m gvgai_pcg.rl.benchmark [hydra overrides]`` trains a short run of the given config
(default: the fast default, PPCG on Zelda), then times the network alone on real observations
(``num_envs`` per acting pass, ``num_envs x n_steps`` per update) in two shapes:

- **the network's whole work** in A2C as the study ran it: ``n_steps + 1`` acting forward
  passes (the rollout's and the bootstrap's) plus the update's forward, backward, clipping and
  RMSprop step over the rollout. This is the limit the end-to-end figure is held against;
- **the reused-graph work** of our loop from 24 envs (``gvgai_pcg.rl.rollout``): the acting passes
  keep their graph, so the update is one backward, clipping and step (plus the bootstrap pass).
  Below 24 envs the loop does the whole work instead, which is cheaper there.

Then it splits one batch of the training loop into acting passes, env steps, update and the
rest. Steady state only: warm-up is left out everywhere; every figure is also given per second
of this process's CPU time, which a loaded machine disturbs less than wall time.
"""

from __future__ import annotations

import copy
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import torch
from omegaconf import DictConfig

from gvgai_pcg.engine.threads import threads_for_batch
from gvgai_pcg.rl.a2c import train
from gvgai_pcg.rl.a2c_loss import A2CLoss
from gvgai_pcg.rl.environment import EnvFactory, make_difficulty
from gvgai_pcg.rl.models import CHANNELS_LAST_TORSOS, as_tensordict_module, make_actor_critic
from gvgai_pcg.rl.rollout import ActingRollouts, keeps_acting_graph, sample_actions

WINDOWS = 5


@dataclass(frozen=True)
class Cost:
    """Seconds per call of some work, wall and CPU (medians over timed windows)."""

    wall: float
    cpu: float


def synchronize() -> None:
    """Wait for the GPU's queued work, so that a clock read after it counts that work (CUDA runs
    asynchronously; nothing to wait for on the CPU)."""
    if torch.cuda.is_available() and torch.cuda.is_initialized():
        torch.cuda.synchronize()


def time_calls(work: Callable[[], None], seconds: float, windows: int = WINDOWS) -> Cost:
    """Median wall and CPU seconds per call of ``work`` over ``windows`` windows."""
    work()  # warm-up
    walls, cpus = [], []
    for _ in range(windows):
        synchronize()
        calls, start, cpu = 0, time.perf_counter(), time.process_time()
        while calls < 2 or time.perf_counter() - start < seconds / windows:
            work()
            calls += 1
        synchronize()
        walls.append((time.perf_counter() - start) / calls)
        cpus.append((time.process_time() - cpu) / calls)
    return Cost(statistics.median(walls), statistics.median(cpus))


def _env_and_net(cfg: DictConfig):
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
    obs_key = cfg.env.obs
    net = make_actor_critic(
        cfg.model.name,
        obs_key,
        tuple(env.observation_spec[obs_key].shape[-3:]),
        env.action_spec.space.n,
        int(cfg.model.hidden),
    ).to(cfg.device)
    optimizer = torch.optim.RMSprop(
        net.parameters(), lr=float(cfg.algo.lr), alpha=cfg.algo.rmsprop_alpha, eps=cfg.algo.rmsprop_eps
    )
    return env, net, optimizer


def layout_costs(cfg: DictConfig, seconds: float = 4.0) -> dict[str, Cost]:
    """Seconds per update (forward and backward over ``num_envs x n_steps`` random tile-like
    observations) of the net in its own memory layout (``"own"``) and contiguous
    (``"contiguous"``), alternated: what ``ActorCritic.memory_format`` buys."""
    env, net, _ = _env_and_net(cfg)
    shape = tuple(env.observation_spec[cfg.env.obs].shape[-3:])
    env.close()
    plain = copy.deepcopy(net).to(memory_format=torch.contiguous_format)
    plain.memory_format = torch.contiguous_format
    generator = torch.Generator().manual_seed(0)
    obs = torch.randint(0, 2, (int(cfg.env.num_envs) * int(cfg.algo.n_steps), *shape), generator=generator)
    obs = (obs if cfg.env.obs == "tiles" else obs * 255).to(torch.uint8).to(cfg.device)

    def update(model: torch.nn.Module) -> Callable[[], None]:
        def work() -> None:
            logits, values = model(obs)
            (logits.logsumexp(-1).mean() + values.square().mean()).backward()

        return work

    quarter = seconds / 4
    own = [time_calls(update(net), quarter), time_calls(update(plain), quarter)]
    own += [time_calls(update(net), quarter), time_calls(update(plain), quarter)]
    return {
        "own": Cost(min(own[0].wall, own[2].wall), min(own[0].cpu, own[2].cpu)),
        "contiguous": Cost(min(own[1].wall, own[3].wall), min(own[1].cpu, own[3].cpu)),
    }


def network_costs(cfg: DictConfig, seconds: float = 6.0) -> dict[str, Cost]:
    """Seconds per batch of the network's whole work (``"acting_and_update"``) and of the
    reused-graph work (``"reused_graph"``), on ``n_steps + 1`` batches of real observations."""
    env, net, optimizer = _env_and_net(cfg)
    obs_key, n_steps = cfg.env.obs, int(cfg.algo.n_steps)
    td = env.reset()
    frames = [td.get(obs_key).clone()]
    for _ in range(n_steps):
        td = env.step_mdp(env.rand_step(td))
        frames.append(td.get(obs_key).clone())
    rollout = torch.cat(frames[:n_steps])
    clip = float(cfg.algo.max_grad_norm)

    def learn(logits: torch.Tensor, values: torch.Tensor) -> None:
        loss = -logits.log_softmax(-1).mean() + values.pow(2).mean()
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(net.parameters(), clip)
        optimizer.step()

    def acting_and_update() -> None:
        with torch.no_grad():
            for obs in frames:
                sample_actions(net(obs)[0])
        learn(*net(rollout))

    def reused_graph() -> None:
        outputs = [net(obs) for obs in frames[:n_steps]]
        for logits, _ in outputs:
            sample_actions(logits)
        with torch.no_grad():
            net(frames[n_steps])
        learn(torch.cat([o[0] for o in outputs]), torch.cat([o[1] for o in outputs]))

    # alternate the two, so that a change of load hits both alike
    half = seconds / 4
    a1, r1 = time_calls(acting_and_update, half), time_calls(reused_graph, half)
    a2, r2 = time_calls(acting_and_update, half), time_calls(reused_graph, half)
    env.close()
    return {
        "acting_and_update": Cost(min(a1.wall, a2.wall), min(a1.cpu, a2.cpu)),
        "reused_graph": Cost(min(r1.wall, r2.wall), min(r1.cpu, r2.cpu)),
    }


class _Stopwatch:
    """Adds up the wall and CPU time spent inside ``with`` blocks; on a GPU each block waits for
    its queued work at its end, which keeps the parts apart but keeps them from overlapping."""

    def __init__(self) -> None:
        self.wall = self.cpu = 0.0

    def __enter__(self) -> None:
        self._start, self._cpu = time.perf_counter(), time.process_time()

    def __exit__(self, *exc) -> None:
        synchronize()
        self.wall += time.perf_counter() - self._start
        self.cpu += time.process_time() - self._cpu


def batch_breakdown(cfg: DictConfig, batches: int = 60) -> dict[str, Cost]:
    """Seconds per batch of the training loop's parts: the acting passes, the env's steps and
    resets, the update (loss, backward, clipping, step) and the rest (rollout bookkeeping)."""
    env, net, optimizer = _env_and_net(cfg)
    parts = {name: _Stopwatch() for name in ("acting", "env", "update")}
    timed_net = _Timed(net, parts["acting"])
    rollouts = ActingRollouts(env, timed_net, cfg.env.obs, int(cfg.algo.n_steps))
    step_and_maybe_reset = env.step_and_maybe_reset

    def timed_step(td):
        with parts["env"]:
            return step_and_maybe_reset(td)

    env.step_and_maybe_reset = timed_step
    loss_module = A2CLoss(as_tensordict_module(net, cfg.env.obs), cfg.algo.gamma)
    total = _Stopwatch()
    for batch in range(batches + 1):
        if batch == 1:  # the first batch is warm-up
            for watch in (*parts.values(), total):
                watch.wall = watch.cpu = 0.0
        with total:
            rollout = rollouts.collect()
            with parts["update"]:
                losses = loss_module(rollout)
                loss = losses["loss_objective"] + losses["loss_critic"] + losses["loss_entropy"]
                optimizer.zero_grad(set_to_none=True)
                loss.backward()
                torch.nn.utils.clip_grad_norm_(net.parameters(), float(cfg.algo.max_grad_norm))
                optimizer.step()
    env.close()
    costs = {name: Cost(w.wall / batches, w.cpu / batches) for name, w in parts.items()}
    costs["total"] = Cost(total.wall / batches, total.cpu / batches)
    costs["rest"] = Cost(
        costs["total"].wall - sum(parts[name].wall for name in parts) / batches,
        costs["total"].cpu - sum(parts[name].cpu for name in parts) / batches,
    )
    return costs


class _Timed(torch.nn.Module):
    """``module`` whose calls are timed by ``watch`` (the acting passes of a rollout)."""

    def __init__(self, module: torch.nn.Module, watch: _Stopwatch) -> None:
        super().__init__()
        self.module, self.watch = module, watch

    def forward(self, *args):
        with self.watch:
            return self.module(*args)


def benchmark(cfg: DictConfig) -> dict[str, float]:
    """End-to-end frames/s of a short training run, the network's limits and the ratios, per wall
    and per CPU second, and the split of one batch (ms)."""
    torch.set_num_threads(int(cfg.threads) or threads_for_batch(int(cfg.env.num_envs)))
    with tempfile.TemporaryDirectory() as tmp:
        result = train(cfg, Path(tmp) / "run")
    frames = int(cfg.env.num_envs) * int(cfg.algo.n_steps) * int(cfg.collector.workers)
    costs = network_costs(cfg)
    limit, reused = costs["acting_and_update"], costs["reused_graph"]
    numbers = {
        "end_to_end_fps": result.fps,
        "end_to_end_cpu_fps": result.cpu_fps,
        "limit_fps": frames / limit.wall,
        "limit_cpu_fps": frames / limit.cpu,
        "reused_limit_fps": frames / reused.wall,
        "reused_limit_cpu_fps": frames / reused.cpu,
        "frames_per_batch": frames,
        # a collector's rollouts carry no graph, whatever the batch
        "keeps_acting_graph": float(
            keeps_acting_graph(int(cfg.env.num_envs)) and int(cfg.collector.workers) == 1
        ),
        "load": os.getloadavg()[0],
    }
    numbers["ratio"] = numbers["end_to_end_fps"] / numbers["limit_fps"]
    numbers["cpu_ratio"] = numbers["end_to_end_cpu_fps"] / numbers["limit_cpu_fps"]
    numbers["reused_ratio"] = numbers["end_to_end_fps"] / numbers["reused_limit_fps"]
    numbers["reused_cpu_ratio"] = numbers["end_to_end_cpu_fps"] / numbers["reused_limit_cpu_fps"]
    if cfg.model.name in CHANNELS_LAST_TORSOS:  # a net kept contiguous has nothing to compare
        layouts = layout_costs(cfg)
        numbers["layout_cpu_speedup"] = layouts["contiguous"].cpu / layouts["own"].cpu
    if int(cfg.collector.workers) == 1:
        for name, cost in batch_breakdown(cfg).items():
            numbers[f"{name}_ms"] = cost.wall * 1e3
            numbers[f"{name}_cpu_ms"] = cost.cpu * 1e3
    return numbers


def describe(name: str, numbers: dict[str, float]) -> str:
    """The benchmark's numbers as a few lines of text."""
    n = numbers
    lines = [
        f"{name}: {n['frames_per_batch']} frames per batch, load {n['load']:.1f}; the loop "
        + ("keeps the acting passes' graph" if n["keeps_acting_graph"] else "recomputes the acting passes"),
        f"  end-to-end           {n['end_to_end_fps']:7.0f} frames/s "
        f"({n['end_to_end_cpu_fps']:.0f} per CPU s)",
        f"  network's whole work {n['limit_fps']:7.0f} frames/s ({n['limit_cpu_fps']:.0f} per CPU s): "
        f"end-to-end is {n['ratio']:.0%} of it ({n['cpu_ratio']:.0%} per CPU s)",
        f"  reused-graph work    {n['reused_limit_fps']:7.0f} frames/s "
        f"({n['reused_limit_cpu_fps']:.0f} per CPU s): "
        f"end-to-end is {n['reused_ratio']:.0%} of it ({n['reused_cpu_ratio']:.0%} per CPU s)",
    ]
    if "layout_cpu_speedup" in n:
        speedup = n["layout_cpu_speedup"]
        lines.append(f"  the net's memory layout: updates {speedup:.2f}x as fast as contiguous")
    if "total_ms" in n:
        split = ", ".join(
            f"{part} {n[f'{part}_cpu_ms']:.1f} ({n[f'{part}_cpu_ms'] / n['total_cpu_ms']:.0%})"
            for part in ("acting", "env", "update", "rest")
        )
        lines.append(f"  one batch, CPU ms: {n['total_cpu_ms']:.1f} = {split}")
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    if {"-h", "--help"} & set(argv):
        print(__doc__.strip())
        return 0
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir

    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        cfg = compose("config", overrides=["log.curve=false", "log.backends=[]", *argv])
    if cfg.algo.name != "a2c":  # the limit it holds training against is A2C's update
        print(
            f"python -m gvgai_pcg.rl.benchmark: algo={cfg.algo.name}: the network's limit is modelled for "
            "algo=a2c only; time another learner's training with gvgai-pcg train",
            file=sys.stderr,
        )
        return 2
    print(describe(cfg.run_name, benchmark(cfg)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
