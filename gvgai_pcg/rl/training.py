"""The training loop shared by every learner, on one natively batched env (or a collector's
workers).

The loop reads like the algorithm: set up the curriculum's run (``CurriculumRun``, which owns
the level choice), the envs, the agent and the collector; then per batch collect a rollout of
``n_steps`` steps of all envs, let the curriculum mark the steps to learn from, hand the rollout
to the learner (``gvgai_pcg.rl.learners``: A2C, PPO, a plug-in's), which takes its update, give
the curriculum its signals, log and checkpoint. Everything around the update is here and the same
for every learner: the env and its level source, the network, the episode log (``log.csv``) and
the update log (``updates.csv``, from the first update on), checkpoints, snapshots, and the
curriculum's hooks (``CurriculumHooks``): before the update the run's ``trains_on`` (the
rollout's ``train_mask``: PLR⊥ trains on replayed levels only); after it, for a curriculum that
learns, the batch's per-level signals (``gvgai_pcg.curricula.signals``) with the learner's
per-step ``advantage``, ``state_value`` and ``value_target`` (``Update.signals``) averaged over
each level's steps, and for one that plays the policy (SFL) the acting policy. A run lives in one
directory and continues from its checkpoint when started again: same frame count, same
difficulty, the logs cut back to the checkpoint.

The session around the loop (``run_session``) makes the run lose nothing: one process per run
directory, every check before the first frame, a stop on SIGINT/SIGTERM after the current
update with a checkpoint, and the divergence guard between the gradient and the optimizer step
(the learner calls it before each step).
"""

from __future__ import annotations

import functools
import gc
import logging
import math
import random
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from tensordict import TensorDictBase
from torchrl.collectors import MultiSyncCollector
from torchrl.envs import EnvBase
from torchrl.modules import ProbabilisticActor

from gvgai_pcg.curricula.base import ActingPolicy, CurriculumRun
from gvgai_pcg.curricula.signals import feedback_for
from gvgai_pcg.engine.step_plan import compile_pays_back
from gvgai_pcg.engine.threads import threads_for_batch
from gvgai_pcg.levels.sets import level_set_fingerprint
from gvgai_pcg.progress import progress
from gvgai_pcg.rl.curves import plot_curve
from gvgai_pcg.rl.environment import EnvFactory, curriculum_run
from gvgai_pcg.rl.fused import fused_step
from gvgai_pcg.rl.learners import learner_class
from gvgai_pcg.rl.learners.base import Learner
from gvgai_pcg.rl.main_guard import refuse_without_main_guard
from gvgai_pcg.rl.models import actor_critic_for, as_tensordict_module
from gvgai_pcg.rl.rollout import ActingRollouts
from gvgai_pcg.rl.run_session import RunSession, open_run
from gvgai_pcg.rundir.checkpoint import CURRICULUM_KEY, restore, save_model
from gvgai_pcg.rundir.provenance import record_session
from gvgai_pcg.rundir.run_log import EpisodeTracker, RunLog
from gvgai_pcg.rundir.snapshots import Snapshots
from gvgai_pcg.rundir.stop_signal import StopSignal, ignoring_stop_signals
from gvgai_pcg.rundir.update_log import UpdateLog, mean_losses

log = logging.getLogger(__name__)

UPDATE_ROWS_EVERY_FRAMES = 10_000  # log.every_update_frames when a config has none


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
    updates_path: Path | None = None  # updates.csv: the update statistics from the first update


def seed_everything(seed: int) -> None:
    random.seed(seed)
    np.random.seed(seed)
    torch.manual_seed(seed)


def train(
    cfg: DictConfig, run_dir: Path, files: dict[str, str] | None = None, stop: StopSignal | None = None
) -> TrainResult:
    """Train (or continue training) the run described by ``cfg`` in ``run_dir``, with the learner
    ``cfg.algo.name``.

    ``files`` (name -> text, e.g. Hydra's ``.hydra/*.yaml``) are written with ``config.yaml`` once
    the session is accepted; ``stop`` receives SIGINT/SIGTERM during it (default: a new one).
    Raises ``DivergenceError`` when an update is not finite, and ``MissingMainGuardError`` (one
    line, before anything is written) when collector workers would run the calling script again."""
    if int(cfg.collector.workers) > 1:
        refuse_without_main_guard()
    torch.set_num_threads(int(cfg.threads) or threads_for_batch(int(cfg.env.num_envs)))
    config = OmegaConf.to_container(cfg, resolve=True)
    files = {"config.yaml": OmegaConf.to_yaml(cfg, resolve=True), **(files or {})}
    level_set = own_level_set(config)
    with open_run(run_dir, config, files, stop, level_set) as session:
        start = int(session.saved["frames"]) if session.saved else 0
        if start < int(cfg.total_frames):  # a finished run started again trains nothing: no row
            record_session(run_dir, start)
        return _train(cfg, run_dir, config, session, level_set)


def start_workers(make_envs: list, policy: torch.nn.Module, **options) -> MultiSyncCollector:
    """The collector of ``make_envs``' worker processes. When a worker fails to start, its error
    goes on without the traceback that holds the half-built collector, which is collected now:
    kept to the interpreter's exit, its weight sync scheme's ``__del__`` starts a queue thread
    there, and the program hangs instead of ending."""
    try:
        return MultiSyncCollector(make_envs, policy, **options)
    except RuntimeError as error:  # a worker died before it said it was ready
        failure = str(error)
    gc.collect()  # the collector's scheme shuts down now, while threads can still start
    raise RuntimeError(f"a collector worker failed to start (its own error is above): {failure}")


def own_level_set(config: dict) -> str | None:
    """The fingerprint of the run's own level files (``regimen.path``), saved in its checkpoints:
    ``None`` for a regimen without one."""
    path = (config.get("regimen") or {}).get("path")
    return level_set_fingerprint(path) if path else None


def _train(
    cfg: DictConfig, run_dir: Path, config: dict, session: RunSession, level_set: str | None = None
) -> TrainResult:
    """The algorithm: set up the curriculum's run, the envs, the agent and the collector; then
    per batch collect, let the curriculum mark the steps to learn from, update, give the
    curriculum its signals, log, and checkpoint; then close the run's outputs."""
    checkpoint_path, saved = session.checkpoint_path, session.saved
    frames = saved["frames"] if saved else 0
    seed_everything(cfg.seed)

    # --- setup: the curriculum's run (it owns the level choice), the envs, the agent ---
    levels = curriculum_run(cfg.regimen, cfg.game.name)
    make_env, env = _make_envs(cfg, levels, frames)
    obs_key = cfg.env.obs
    net, policy, learner = _make_agent(cfg, env)
    episodes, elapsed = 0, 0.0
    if saved:
        restore(saved, net, learner, levels)  # the checkpoint's "optimizer" is the learner's state
        episodes, elapsed = saved["episodes"], saved["elapsed"]
        log.info("resuming %s at %d frames (difficulty %s)", run_dir, frames, levels.difficulty)
    workers = int(cfg.collector.workers)
    frames_per_batch = workers * int(cfg.env.num_envs) * learner.n_steps
    remaining = max(0, int(cfg.total_frames) - frames)
    remaining = math.ceil(remaining / frames_per_batch) * frames_per_batch
    collector = _make_collector(cfg, session, make_env, env, net, policy, learner, remaining)

    run_log = RunLog(run_dir, list(cfg.log.backends), resume_frames=frames if saved else None)
    update_log = UpdateLog(run_dir, run_log.loggers, resume_frames=frames if saved else None)
    update_every = int(cfg.log.get("every_update_frames", UPDATE_ROWS_EVERY_FRAMES))
    next_update_row = frames  # the first update of a session writes a row
    rows_every = int(cfg.log.every_episodes)
    tracker = EpisodeTracker(workers * int(cfg.env.num_envs))
    losses_since_row: list[torch.Tensor] = []
    losses_since_update_row: list[torch.Tensor] = []
    hooks = CurriculumHooks(levels, obs_key, cfg.device)
    every = int(cfg.checkpoint.every_frames)
    next_checkpoint = (frames // every + 1) * every
    snapshots = Snapshots(run_dir, int(cfg.checkpoint.get("keep_every_frames", 0)), frames)
    bar = progress(int(cfg.total_frames), "train", "frame", initial=frames)
    row_frames, row_time, start = frames, time.perf_counter(), time.perf_counter()
    start -= elapsed
    update_row_frames, update_row_time, updates = frames, row_time, 0

    def checkpoint() -> None:
        state = {
            "frames": frames,
            "episodes": episodes,
            "elapsed": time.perf_counter() - start,
            "model": net.state_dict(),
            "optimizer": learner.state_dict(),
            CURRICULUM_KEY: levels.state_dict(),
            "config": config,
            "log_rows": run_log.rows,
            "level_set": level_set,
        }
        update_log.sync()
        session.save_checkpoint(state, net, run_log)  # the log on disk first; never a non-finite model

    session.saving_last_state(checkpoint)  # whatever stops the loop, the last complete update is kept

    steady_frames, steady_start, steady_cpu = frames, None, 0.0
    for rollout in session.guard.watch(collector if remaining > 0 else [], net):
        rollout = rollout.reshape(-1, rollout.shape[-1])  # [envs, n_steps] (workers stacked)
        tracker.update(rollout)

        hooks.before_update(rollout)

        # --- update: the learner's, checked by the divergence guard before each step ---
        check = functools.partial(session.guard.check_update, frames=frames + rollout.numel())
        update = learner.update(rollout, check)
        if workers > 1:
            collector.update_policy_weights_()
        frames += rollout.numel()
        updates += 1
        bar.update(rollout.numel())
        stacked = update.stacked()
        losses_since_row.append(stacked)
        losses_since_update_row.append(stacked)
        hooks.after_update(rollout, update, net, frames)

        # --- update log: the first update, then every log.every_update_frames ---
        if frames >= next_update_row:
            now = time.perf_counter()
            policy_loss, value_loss, entropy = mean_losses(losses_since_update_row)
            losses_since_update_row.clear()
            update_log.write(
                {
                    "frames": frames,
                    "updates": updates,
                    "policy_loss": policy_loss,
                    "value_loss": value_loss,
                    "entropy": entropy,
                    "fps": (frames - update_row_frames) / max(now - update_row_time, 1e-9),
                    "time": now - start,
                }
            )
            update_row_frames, update_row_time = frames, now
            next_update_row = (frames // update_every + 1) * update_every

        # --- episode log: a row when enough episodes have finished ---
        if len(tracker) >= rows_every:
            now = time.perf_counter()
            stats = tracker.take()
            episodes += stats["episodes"]
            policy_loss, value_loss, entropy = mean_losses(losses_since_row)
            losses_since_row.clear()
            row = {
                **stats,
                "frames": frames,
                "episodes": episodes,
                "difficulty": levels.difficulty,
                "policy_loss": policy_loss,
                "value_loss": value_loss,
                "entropy": entropy,
                "fps": (frames - row_frames) / max(now - row_time, 1e-9),
                "time": now - start,
            }
            run_log.write(row)
            bar.set_postfix(
                score=f"{row['mean_score']:.2f}",
                **({} if levels.state is None else {"d": f"{row['difficulty']:.2f}"}),
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
    update_log.close()
    if run_log.rows == 0 and updates > 0:
        sys.stderr.write(
            f"gvgai-pcg train: {frames} frames and no row in {run_log.path.name} yet (a row needs "
            f"log.every_episodes={rows_every} finished episodes); the update statistics are in "
            f"{update_log.path}\n"
        )
    stopped_by = session.stop.name if session.stop.received and frames < cfg.total_frames else None
    model_path = None
    if not stopped_by:  # an unfinished run: the checkpoint is all it needs to go on
        model_path = run_dir / "model.pt"
        save_model(model_path, net.state_dict(), config, frames)
    curve_path = None
    if cfg.log.curve:  # a stopped run's curve so far too: it is what a user looks at first
        curve_path = plot_curve(run_log.path, run_dir / "curve.png", title=cfg.run_name)
    return TrainResult(
        run_dir,
        frames,
        run_log.path,
        checkpoint_path,
        model_path,
        curve_path,
        fps,
        cpu_fps,
        stopped_by,
        update_log.path,
    )


class CurriculumHooks:
    """The loop's two calls to the curriculum's run: ``before_update`` (the steps the learner may
    take gradients from: PLR⊥ keeps new levels out) and ``after_update`` (what happened on each
    level, with the learner's per-step signals; then the new policy, to a curriculum that plays
    it). Signals are computed only for a curriculum that learns, a policy built only for one that
    plays it."""

    LEARNING = ("advantage", "state_value", "value_target")

    def __init__(self, run: CurriculumRun, obs_key: str, device: str) -> None:
        self.run, self.obs_key, self.device = run, obs_key, device
        self.feedback = feedback_for(run)
        self.plays_policy = run.plays_policy

    def before_update(self, rollout: TensorDictBase) -> None:
        if self.feedback is not None:
            self.feedback.mark_trained_steps(rollout)

    def after_update(self, rollout: TensorDictBase, update, net: torch.nn.Module, frames: int) -> None:
        if self.feedback is not None:
            signals = update.signals or {}
            self.feedback(rollout, **{key: signals.get(key) for key in self.LEARNING})
        if self.plays_policy:
            self.run.between_updates(acting_policy(net, self.obs_key, self.device), frames)


def acting_policy(net: torch.nn.Module, obs_key: str, device: str):
    """The network as a sampling policy for a curriculum that plays it (``between_updates``)."""

    def act(tensordict) -> torch.Tensor:
        logits, _ = net(tensordict.get(obs_key))
        return torch.distributions.Categorical(logits=logits, validate_args=False).sample()

    return ActingPolicy(act, obs_key, str(device))


def _make_envs(cfg: DictConfig, levels: CurriculumRun, frames: int) -> tuple[EnvFactory, EnvBase]:
    """The recipe of the training env (one batched ``GVGAIEnv`` per collector worker, every one
    around the run's shared state) and an env of this process: the one it trains on with one
    worker, else one that only shows the specs (around a spare state, so that the run's own
    transform reaches the workers without a parent)."""
    make_env = EnvFactory(
        game=cfg.game.name,
        regimen=cfg.regimen,
        num_envs=int(cfg.env.num_envs),
        obs=cfg.env.obs,
        max_steps=int(cfg.env.max_steps),
        device=cfg.device,
        seed=int(cfg.seed) * 1_000_003 + frames,  # a resumed run plays new episodes
        run=levels,
        # what is left of the run, in batched steps: a short job ticks eagerly (the same steps)
        compile_tick=compile_pays_back((int(cfg.total_frames) - frames) // int(cfg.env.num_envs), cfg.device),
    )
    if int(cfg.collector.workers) == 1:
        return make_env, make_env()
    return make_env, replace(make_env, run=levels.spare())()


def _make_agent(cfg: DictConfig, env: EnvBase) -> tuple[torch.nn.Module, ProbabilisticActor, Learner]:
    """The shared-torso actor-critic, the policy that samples its actions, and the learner."""
    net = actor_critic_for(env, cfg.model, cfg.env.obs).to(cfg.device)
    actor_critic = as_tensordict_module(net, cfg.env.obs)
    policy = ProbabilisticActor(
        actor_critic,
        in_keys=["logits"],
        out_keys=["action"],
        distribution_class=torch.distributions.Categorical,
        distribution_kwargs={"validate_args": False},  # the checks cost ~25% of an acting step
        spec=env.action_spec,
    )
    learner: Learner = learner_class(cfg.algo.name)(cfg.algo, net, actor_critic)
    return net, policy, learner


def _make_collector(
    cfg: DictConfig,
    session: RunSession,
    make_env: EnvFactory,
    env: EnvBase,
    net: torch.nn.Module,
    policy: ProbabilisticActor,
    learner: Learner,
    remaining: int,
):
    """The rollouts of ``n_steps`` steps of every env: this process's env (one worker), or the
    workers' processes, which share the curriculum's state through files in the run directory."""
    workers = int(cfg.collector.workers)
    if workers == 1:
        # from 24 envs A2C's acting passes keep their graph for the update (gvgai_pcg.rl.rollout)
        keep_graph, fused = learner.keep_acting_graph, fused_step(cfg.get("rollout", "auto"), env, net)
        return session.closing(ActingRollouts(env, net, cfg.env.obs, learner.n_steps, keep_graph, fused))
    if cfg.get("rollout", "auto") == "fused":
        raise ValueError(f"rollout=fused: collector workers ({workers}) roll out unfused; use rollout=auto")
    env.close()
    make_env.run.share_through(session.run_dir / "shared")
    frames_per_batch = workers * int(cfg.env.num_envs) * learner.n_steps
    collector = start_workers(
        [ignoring_stop_signals(functools.partial(make_env, worker=i)) for i in range(workers)],
        policy,
        frames_per_batch=frames_per_batch,
        total_frames=max(remaining, frames_per_batch),  # a finished run collects nothing
    )
    return session.closing(collector)
