"""A2C training, as the study ran it (GENERATORS.md §3), on one natively batched env.

The loop reads like the algorithm: collect ``n_steps`` steps of all envs (the rollout),
compute n-step returns and the three losses (``A2CLoss``), take one RMSprop step with the
gradient norm clipped, then log and checkpoint. Every number comes from the config
(``conf/algo/a2c.yaml``). A run lives in one directory and continues from its checkpoint when
started again: same frame count, same difficulty, the log cut back to the checkpoint.

The session around the loop (``run_session``) makes the run lose nothing: one process per run
directory, every check before the first frame, a stop on SIGINT/SIGTERM after the current
update with a checkpoint, and the divergence guard between the gradient and the optimizer step.
"""

from __future__ import annotations

import functools
import logging
import math
import random
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from torchrl.collectors import MultiSyncCollector
from torchrl.modules import ProbabilisticActor

from gvgai_pcg.progress import progress
from gvgai_pcg.rl.a2c_loss import A2CLoss
from gvgai_pcg.rl.checkpoint import restore, save_model
from gvgai_pcg.rl.curves import plot_curve
from gvgai_pcg.rl.environment import EnvFactory, make_difficulty
from gvgai_pcg.rl.models import as_tensordict_module, make_actor_critic
from gvgai_pcg.rl.provenance import record_session
from gvgai_pcg.rl.rollout import ActingRollouts
from gvgai_pcg.rl.run_log import EpisodeTracker, RunLog
from gvgai_pcg.rl.run_session import RunSession, open_run
from gvgai_pcg.rl.snapshots import Snapshots
from gvgai_pcg.rl.stop_signal import StopSignal, ignoring_stop_signals

log = logging.getLogger(__name__)


@dataclass
class TrainResult:
    """Where a finished run left its outputs."""

    run_dir: Path
    frames: int
    log_path: Path
    checkpoint_path: Path
    model_path: Path | None  # None when the session was stopped before the end
    curve_path: Path | None
    fps: float  # steady-state frames/s of this session (from the end of its first batch)
    cpu_fps: float  # the same per second of this process's CPU time (robust to a loaded machine)
    stopped_by: str | None = None  # "SIGINT"/"SIGTERM" when a signal stopped it early


def seed_everything(seed: int) -> None:
    random.seed(seed)
    np.random.seed(seed)
    torch.manual_seed(seed)


def train(
    cfg: DictConfig, run_dir: Path, files: dict[str, str] | None = None, stop: StopSignal | None = None
) -> TrainResult:
    """Train (or continue training) the run described by ``cfg`` in ``run_dir``.

    ``files`` (name -> text, e.g. Hydra's ``.hydra/*.yaml``) are written with ``config.yaml`` once
    the session is accepted; ``stop`` receives SIGINT/SIGTERM during it (default: a new one).
    Raises ``DivergenceError`` when an update is not finite."""
    if cfg.threads:
        torch.set_num_threads(int(cfg.threads))
    config = OmegaConf.to_container(cfg, resolve=True)
    files = {"config.yaml": OmegaConf.to_yaml(cfg, resolve=True), **(files or {})}
    with open_run(run_dir, config, files, stop) as session:
        start = int(session.saved["frames"]) if session.saved else 0
        if start < int(cfg.total_frames):  # a finished run started again trains nothing: no row
            record_session(run_dir, start)
        return _train(cfg, run_dir, config, session)


def _train(cfg: DictConfig, run_dir: Path, config: dict, session: RunSession) -> TrainResult:
    checkpoint_path, saved = session.checkpoint_path, session.saved
    frames = saved["frames"] if saved else 0
    seed_everything(cfg.seed)

    # --- env: one batched GVGAIEnv per collector worker, one shared difficulty ---
    algo, workers = cfg.algo, int(cfg.collector.workers)
    difficulty = make_difficulty(cfg.regimen, cfg.game.name)
    make_env = EnvFactory(
        game=cfg.game.name,
        regimen=cfg.regimen,
        num_envs=int(cfg.env.num_envs),
        obs=cfg.env.obs,
        max_steps=int(cfg.env.max_steps),
        device=cfg.device,
        seed=int(cfg.seed) * 1_000_003 + frames,  # a resumed run plays new episodes
        difficulty=difficulty,
    )
    # worker processes attach the shared transform themselves; the main process probes the specs
    # on an env of its own so that the shared transform reaches them without a parent
    env = (
        make_env()
        if workers == 1
        else replace(make_env, difficulty=make_difficulty(cfg.regimen, cfg.game.name))()
    )
    obs_key = cfg.env.obs

    # --- agent: shared-torso actor-critic; the policy samples actions ---
    net = make_actor_critic(
        cfg.model.name,
        obs_key,
        tuple(env.observation_spec[obs_key].shape[-3:]),
        env.action_spec.space.n,
        int(cfg.model.hidden),
    ).to(cfg.device)
    actor_critic = as_tensordict_module(net, obs_key)
    policy = ProbabilisticActor(
        actor_critic,
        in_keys=["logits"],
        out_keys=["action"],
        distribution_class=torch.distributions.Categorical,
        distribution_kwargs={"validate_args": False},  # the checks cost ~25% of an acting step
        spec=env.action_spec,
    )
    loss_module = A2CLoss(actor_critic, algo.gamma, algo.entropy_coef, algo.value_coef)
    optimizer = torch.optim.RMSprop(
        net.parameters(), lr=algo.lr, alpha=algo.rmsprop_alpha, eps=algo.rmsprop_eps
    )
    episodes, elapsed = 0, 0.0
    if saved:
        restore(saved, net, optimizer, difficulty)
        episodes, elapsed = saved["episodes"], saved["elapsed"]
        log.info("resuming %s at %d frames (difficulty %s)", run_dir, frames, _difficulty_of(difficulty))

    # --- collector: frames per batch = envs x n_steps ---
    frames_per_batch = workers * int(cfg.env.num_envs) * int(algo.n_steps)
    remaining = max(0, int(cfg.total_frames) - frames)
    remaining = math.ceil(remaining / frames_per_batch) * frames_per_batch
    if workers == 1:
        # from 24 envs the acting passes keep their graph for the update (gvgai_pcg.rl.rollout)
        collector = session.closing(ActingRollouts(env, net, obs_key, int(algo.n_steps)))
    else:
        env.close()
        if difficulty is not None:
            difficulty.share_through(run_dir / "shared")
        collector = MultiSyncCollector(
            [ignoring_stop_signals(functools.partial(make_env, worker=i)) for i in range(workers)],
            policy,
            frames_per_batch=frames_per_batch,
            total_frames=max(remaining, frames_per_batch),  # a finished run collects nothing
        )
        session.closing(collector)

    run_log = RunLog(run_dir, list(cfg.log.backends), resume_frames=frames if saved else None)
    rows_every = int(cfg.log.every_episodes)
    tracker = EpisodeTracker(workers * int(cfg.env.num_envs))
    losses_since_row: list[torch.Tensor] = []
    every = int(cfg.checkpoint.every_frames)
    next_checkpoint = (frames // every + 1) * every
    snapshots = Snapshots(run_dir, int(cfg.checkpoint.get("keep_every_frames", 0)), frames)
    bar = progress(int(cfg.total_frames), "train", "frame", initial=frames)
    row_frames, row_time, start = frames, time.perf_counter(), time.perf_counter() - elapsed

    def checkpoint() -> None:
        state = {
            "frames": frames,
            "episodes": episodes,
            "elapsed": time.perf_counter() - start,
            "model": net.state_dict(),
            "optimizer": optimizer.state_dict(),
            "difficulty": difficulty.state_dict() if difficulty is not None else None,
            "config": config,
            "log_rows": run_log.rows,
        }
        session.save_checkpoint(state, net, run_log)  # the log on disk first; never a non-finite model

    session.saving_last_state(checkpoint)  # whatever stops the loop, the last complete update is kept

    steady_frames, steady_start, steady_cpu = frames, None, 0.0
    for rollout in session.guard.watch(collector if remaining > 0 else [], net):
        rollout = rollout.reshape(-1, rollout.shape[-1])  # [envs, n_steps] (workers stacked)
        tracker.update(rollout)

        # --- update: n-step returns, losses, one clipped RMSprop step ---
        losses = loss_module(rollout)
        loss = losses["loss_objective"] + losses["loss_critic"] + losses["loss_entropy"]
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        grad_norm = torch.nn.utils.clip_grad_norm_(net.parameters(), algo.max_grad_norm)
        session.guard.check_update(loss, grad_norm, frames + rollout.numel())  # before it is applied
        optimizer.step()
        if workers > 1:
            collector.update_policy_weights_()
        frames += rollout.numel()
        bar.update(rollout.numel())
        losses_since_row.append(
            torch.stack([losses["loss_objective"].detach(), losses["value_loss"], losses["entropy"]])
        )

        # --- log: a row when enough episodes have finished ---
        if len(tracker) >= rows_every:
            now = time.perf_counter()
            stats = tracker.take()
            episodes += stats["episodes"]
            policy_loss, value_loss, entropy = torch.stack(losses_since_row).mean(0).tolist()
            losses_since_row.clear()
            row = {
                **stats,
                "frames": frames,
                "episodes": episodes,
                "difficulty": _difficulty_of(difficulty),
                "policy_loss": policy_loss,
                "value_loss": value_loss,
                "entropy": entropy,
                "fps": (frames - row_frames) / max(now - row_time, 1e-9),
                "time": now - start,
            }
            run_log.write(row)
            bar.set_postfix(
                score=f"{row['mean_score']:.2f}",
                **({} if difficulty is None else {"d": f"{row['difficulty']:.2f}"}),
            )
            row_frames, row_time = frames, now

        if steady_start is None:
            steady_frames, steady_start, steady_cpu = frames, time.perf_counter(), time.process_time()
        snapshots.maybe_keep(frames, net, config)  # before a checkpoint past it: a resume redoes it
        if frames >= next_checkpoint:
            checkpoint()
            next_checkpoint = (frames // every + 1) * every
        if frames >= cfg.total_frames or session.stop.received:
            break

    fps = cpu_fps = math.nan
    if steady_start is not None and frames > steady_frames:
        fps = (frames - steady_frames) / (time.perf_counter() - steady_start)
        cpu_fps = (frames - steady_frames) / (time.process_time() - steady_cpu)
    bar.close()
    collector.shutdown()
    run_log.close()
    checkpoint()
    stopped_by = session.stop.name if session.stop.received and frames < cfg.total_frames else None
    if stopped_by:  # an unfinished run: the checkpoint is all it needs
        return TrainResult(
            run_dir, frames, run_log.path, checkpoint_path, None, None, fps, cpu_fps, stopped_by
        )
    model_path = run_dir / "model.pt"
    save_model(model_path, net.state_dict(), config, frames)
    curve_path = None
    if cfg.log.curve:
        curve_path = plot_curve(run_log.path, run_dir / "curve.png", title=cfg.run_name)
    return TrainResult(run_dir, frames, run_log.path, checkpoint_path, model_path, curve_path, fps, cpu_fps)


def _difficulty_of(difficulty) -> float:
    return difficulty.difficulty if difficulty is not None else math.nan
