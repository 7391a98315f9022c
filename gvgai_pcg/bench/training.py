"""Training throughput: end-to-end frames/s against the network's own limit.

``python -m gvgai_pcg.bench.training [hydra overrides]`` trains a short run of the given config
(default: the fast default, PPCG on Zelda), then times the network alone on real observations
(``num_envs`` per acting pass, ``num_envs x n_steps`` per update) in two shapes:

- **the network's whole work** in the learner's algorithm, the limit the end-to-end figure is held
  against: ``n_steps + 1`` acting forward passes without a graph (the rollout's and the
  bootstrap's), then the update's optimizer steps, each a forward, backward, clipping and step of
  the learner's optimizer. For A2C as the study ran it, one RMSprop step over the whole rollout.
  For PPO, ``epochs x minibatches`` Adam steps, each over a shuffled ``1/minibatches`` of the
  rollout: the work of the reference implementations (Kostrikov's PPO, which level-replay and
  dcd build on), whose acting passes record the values that GAE needs. Our PPO recomputes them
  (TorchRL's GAE evaluates the value of every observation and next observation again, two
  passes without a graph over the rollout): that is loop overhead, outside the limit, and shows
  in the end-to-end ratio. The loss is a stand-in of the same shapes (a log-softmax and a value
  term): the network's forward and backward dominate the real loss's elementwise work;
- **the reused-graph work** of A2C's loop from 24 envs (``gvgai_pcg.rl.rollout``): the acting
  passes keep their graph, so the update is one backward, clipping and step (plus the bootstrap
  pass). Below 24 envs the loop does the whole work instead, which is cheaper there. PPO's
  minibatches are evaluated at the current weights, so it has no such shape.

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
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import torch
from omegaconf import DictConfig

from gvgai_pcg.bench.timing import Stopwatch, time_windows
from gvgai_pcg.config import ConfigError, check_jobs, config_dir
from gvgai_pcg.engine.threads import threads_for_batch
from gvgai_pcg.rl.environment import EnvFactory
from gvgai_pcg.rl.fused import fused_step
from gvgai_pcg.rl.learners import learner_class
from gvgai_pcg.rl.learners.base import Learner
from gvgai_pcg.rl.models import CHANNELS_LAST_TORSOS, actor_critic_for, as_tensordict_module
from gvgai_pcg.rl.rollout import ActingRollouts, keeps_acting_graph, sample_actions
from gvgai_pcg.rl.training import train

WINDOWS = 5
MODELLED = ("a2c", "ppo")  # the learners whose update shape the limit models


@dataclass(frozen=True)
class Cost:
    """Seconds per call of some work, wall and CPU (medians over timed windows)."""

    wall: float
    cpu: float


def time_calls(work: Callable[[], None], seconds: float, windows: int = WINDOWS) -> Cost:
    """Median wall and CPU seconds per call of ``work`` over ``windows`` windows."""
    work()  # warm-up

    def call() -> int:
        work()
        return 1

    timed = time_windows(call, seconds, windows, min_calls=2, sync=True)
    return Cost(
        statistics.median(w.wall / w.calls for w in timed), statistics.median(w.cpu / w.calls for w in timed)
    )


def _env_and_net(cfg: DictConfig):
    """The config's env, network and learner (its optimizer is the one the update steps)."""
    env = EnvFactory(
        cfg.game.name,
        cfg.regimen,
        int(cfg.env.num_envs),
        cfg.env.obs,
        int(cfg.env.max_steps),
        cfg.device,
        int(cfg.seed),
    )()
    obs_key = cfg.env.obs
    net = actor_critic_for(env, cfg.model, obs_key).to(cfg.device)
    learner: Learner = learner_class(cfg.algo.name)(cfg.algo, net, as_tensordict_module(net, obs_key))
    return env, net, learner


def update_shape(algo: DictConfig) -> tuple[int, int]:
    """``(epochs, minibatches)`` of one update: passes over the rollout, optimizer steps a pass
    (A2C: one step over the whole rollout; PPO: its ``epochs`` and ``minibatches``)."""
    if algo.name not in MODELLED:
        raise ValueError(f"algo={algo.name}: the network's limit is modelled for {', '.join(MODELLED)} only")
    return int(algo.get("epochs", 1)), int(algo.get("minibatches", 1))


def reuses_acting_graph(keep: bool | None, num_envs: int) -> bool:
    """Whether the training loop's rollouts keep the acting passes' graph, for a learner whose
    ``keep_acting_graph`` is ``keep``."""
    return keeps_acting_graph(num_envs) if keep is None else bool(keep)


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
    """Seconds per batch of the network's whole work (``"acting_and_update"``) and, for a learner
    that can keep the acting passes' graph (A2C), of the reused-graph work (``"reused_graph"``),
    on ``n_steps + 1`` batches of real observations."""
    env, net, learner = _env_and_net(cfg)
    obs_key, n_steps = cfg.env.obs, int(cfg.algo.n_steps)
    epochs, minibatches = update_shape(cfg.algo)
    td = env.reset()
    frames = [td.get(obs_key).clone()]
    for _ in range(n_steps):
        td = env.step_mdp(env.rand_step(td))
        frames.append(td.get(obs_key).clone())
    rollout = torch.cat(frames[:n_steps])
    clip = float(cfg.algo.max_grad_norm)
    optimizer = learner.optimizer

    def learn(logits: torch.Tensor, values: torch.Tensor) -> None:
        loss = -logits.log_softmax(-1).mean() + values.pow(2).mean()
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(net.parameters(), clip)
        optimizer.step()

    def update() -> None:
        if minibatches == 1 and epochs == 1:  # A2C: the whole rollout, as it was always timed
            learn(*net(rollout))
            return
        for _ in range(epochs):
            for indices in torch.randperm(rollout.shape[0], device=rollout.device).chunk(minibatches):
                learn(*net(rollout[indices]))

    def acting_and_update() -> None:
        with torch.no_grad():
            for obs in frames:
                sample_actions(net(obs)[0])
        update()

    def reused_graph() -> None:
        outputs = [net(obs) for obs in frames[:n_steps]]
        for logits, _ in outputs:
            sample_actions(logits)
        with torch.no_grad():
            net(frames[n_steps])
        learn(torch.cat([o[0] for o in outputs]), torch.cat([o[1] for o in outputs]))

    shapes = {"acting_and_update": acting_and_update}
    if learner.keep_acting_graph is not False:  # PPO evaluates its minibatches at the current weights
        shapes["reused_graph"] = reused_graph
    # alternate the shapes, so that a change of load hits them alike
    part = seconds / (2 * len(shapes))
    first = {name: time_calls(work, part) for name, work in shapes.items()}
    second = {name: time_calls(work, part) for name, work in shapes.items()}
    env.close()
    return {
        name: Cost(min(first[name].wall, second[name].wall), min(first[name].cpu, second[name].cpu))
        for name in shapes
    }


def batch_breakdown(cfg: DictConfig, batches: int = 60) -> dict[str, Cost]:
    """Seconds per batch of the training loop's parts: the acting passes, the env's steps and
    resets, the learner's update (its loss, backward passes, clipping and steps) and the rest
    (rollout bookkeeping). With the fused rollout (``cfg.rollout``, ``gvgai_pcg.rl.fused``)
    "acting" is the fused call (acting pass, sampling and tick) and "env" what the env's step
    adds around it (TorchRL's step plumbing, transforms, resets)."""
    env, net, learner = _env_and_net(cfg)
    parts = {name: Stopwatch(sync=True) for name in ("acting", "env", "update")}
    fused = fused_step(cfg.get("rollout", "auto"), env, net)
    timed_net = _Timed(net, parts["acting"])
    if fused is not None:  # the acting pass runs in one call with the tick: "acting" times that call

        def timed_fused(obs: torch.Tensor):
            with parts["acting"]:
                return fused(obs)

    rollouts = ActingRollouts(
        env,
        net if fused is not None else timed_net,
        cfg.env.obs,
        learner.n_steps,
        keep_graph=learner.keep_acting_graph,
        fused=timed_fused if fused is not None else None,
    )
    step_and_maybe_reset = env.step_and_maybe_reset

    def timed_step(td):
        with parts["env"]:
            return step_and_maybe_reset(td)

    env.step_and_maybe_reset = timed_step
    total = Stopwatch(sync=True)
    for batch in range(batches + 1):
        if batch == 1:  # the first batch is warm-up
            for watch in (*parts.values(), total):
                watch.reset()
        with total:
            rollout = rollouts.collect()
            with parts["update"]:
                learner.update(rollout, lambda loss, grad_norm: None)
    env.close()
    costs = {name: Cost(w.wall / batches, w.cpu / batches) for name, w in parts.items()}
    costs["total"] = Cost(total.wall / batches, total.cpu / batches)
    costs["fused"] = Cost(float(fused is not None), float(fused is not None))
    costs["rest"] = Cost(
        costs["total"].wall - sum(parts[name].wall for name in parts) / batches,
        costs["total"].cpu - sum(parts[name].cpu for name in parts) / batches,
    )
    return costs


class _Timed(torch.nn.Module):
    """``module`` whose calls are timed by ``watch`` (the acting passes of a rollout)."""

    def __init__(self, module: torch.nn.Module, watch: Stopwatch) -> None:
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
    limit = costs["acting_and_update"]
    keep = learner_class(cfg.algo.name).keep_acting_graph
    numbers = {
        "end_to_end_fps": result.fps,
        "end_to_end_cpu_fps": result.cpu_fps,
        "limit_fps": frames / limit.wall,
        "limit_cpu_fps": frames / limit.cpu,
        "frames_per_batch": frames,
        # a collector's rollouts carry no graph, whatever the batch
        "keeps_acting_graph": float(
            reuses_acting_graph(keep, int(cfg.env.num_envs)) and int(cfg.collector.workers) == 1
        ),
        "load": os.getloadavg()[0],
    }
    numbers["ratio"] = numbers["end_to_end_fps"] / numbers["limit_fps"]
    numbers["cpu_ratio"] = numbers["end_to_end_cpu_fps"] / numbers["limit_cpu_fps"]
    if "reused_graph" in costs:
        reused = costs["reused_graph"]
        numbers["reused_limit_fps"] = frames / reused.wall
        numbers["reused_limit_cpu_fps"] = frames / reused.cpu
        numbers["reused_ratio"] = numbers["end_to_end_fps"] / numbers["reused_limit_fps"]
        numbers["reused_cpu_ratio"] = numbers["end_to_end_cpu_fps"] / numbers["reused_limit_cpu_fps"]
    if cfg.model.name in CHANNELS_LAST_TORSOS:  # a net kept contiguous has nothing to compare
        layouts = layout_costs(cfg)
        numbers["layout_cpu_speedup"] = layouts["contiguous"].cpu / layouts["own"].cpu
    if int(cfg.collector.workers) == 1:
        for name, cost in batch_breakdown(cfg).items():
            if name == "fused":  # a flag, not a cost
                numbers["fused"] = cost.wall
                continue
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
    ]
    if "reused_limit_fps" in n:
        lines.append(
            f"  reused-graph work    {n['reused_limit_fps']:7.0f} frames/s "
            f"({n['reused_limit_cpu_fps']:.0f} per CPU s): "
            f"end-to-end is {n['reused_ratio']:.0%} of it ({n['reused_cpu_ratio']:.0%} per CPU s)"
        )
    if "layout_cpu_speedup" in n:
        speedup = n["layout_cpu_speedup"]
        lines.append(f"  the net's memory layout: updates {speedup:.2f}x as fast as contiguous")
    if "total_ms" in n:
        split = ", ".join(
            f"{part} {n[f'{part}_cpu_ms']:.1f} ({n[f'{part}_cpu_ms'] / n['total_cpu_ms']:.0%})"
            for part in ("acting", "env", "update", "rest")
        )
        if n.get("fused"):
            split += " (fused: acting = the fused call with the tick; env = the step's plumbing, resets)"
        lines.append(f"  one batch, CPU ms: {n['total_cpu_ms']:.1f} = {split}")
    return "\n".join(lines)


PROG = "python -m gvgai_pcg.bench.training"


def main(argv: list[str]) -> int:
    if {"-h", "--help"} & set(argv):
        print(__doc__.strip())
        return 0
    from hydra import compose, initialize_config_dir
    from hydra.errors import HydraException

    overrides = ["log.curve=false", "log.backends=[]", *argv]
    try:  # a bad override is one line naming it, as gvgai-pcg train says it, before any work
        check_jobs([overrides])
        with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
            cfg = compose("config", overrides=overrides)
    except (ConfigError, HydraException) as error:
        print(f"{PROG}: {str(error).splitlines()[0]}", file=sys.stderr)
        return 2
    if cfg.algo.name not in MODELLED:  # the limit models each learner's update shape
        print(
            f"{PROG}: algo={cfg.algo.name}: the network's limit is modelled for "
            f"algo={' and algo='.join(MODELLED)} only; time another learner's training with gvgai-pcg train",
            file=sys.stderr,
        )
        return 2
    print(describe(cfg.run_name, benchmark(cfg)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
