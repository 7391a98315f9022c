"""Whole jobs in the bench: the study's evaluation protocol on one run, and a short training job.

Short jobs should cost what the engine's batched speed says, not what compiling costs:
the protocol on one run (30 + 30 generated levels played once, 5 human levels x 30 episodes, at
most 2,000 steps) in at most 30 s on 2 cores, and a 20k-frame training job at most 1.3x its time
with compiling off. Both are timed here in the same run as the env tables:

- the protocol: ``evaluate_policy`` of a model published in the repository (``EVALUATED_RUN``,
  the pilot's 10M-frame Zelda PCG 1 run), in this process, wall and CPU seconds;
- training: ``gvgai-pcg train game=frogs total_frames=20000`` in a child process three times:
  with an empty inductor cache (cold: every graph compiled), again with that cache (warm: what a
  machine that has trained before pays) and with ``GVGAI_PCG_COMPILE=0`` (eager), each into a
  run directory of its own under a temporary folder.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from gvgai_pcg.bench.targets import PROTOCOL_SECONDS, TRAINING_OVER_EAGER, Check, Section, ratio
from gvgai_pcg.bench.timing import Stopwatch
from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.evaluator import evaluate_policy
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.evaluation.protocol import Protocol

if TYPE_CHECKING:
    from gvgai_pcg.evaluation.protocol import Protocol

EVALUATED_RUN = Path(__file__).resolve().parents[2] / "results/pilot/runs/p-e64-lr2e-3-pcg1-s0"
TRAINING_GAME = "frogs"
TRAINING_FRAMES = 20_000
TRAINING_MODES = ("cold", "warm", "eager")
TRAINING_TIMEOUT_S = 600
TIMED_OUT = 124  # the returncode recorded for a child killed at TRAINING_TIMEOUT_S


@dataclass(frozen=True)
class ProtocolTime:
    run: str
    game: str
    episodes: int
    env_steps: int
    wall_s: float
    cpu_s: float


@dataclass(frozen=True)
class TrainingTime:
    mode: str  # one of TRAINING_MODES
    wall_s: float
    returncode: int


def time_protocol(run_dir: Path = EVALUATED_RUN, protocol: Protocol | None = None) -> ProtocolTime:
    """The study's protocol (or ``protocol``) on the model of ``run_dir``, timed from loading it."""
    with Stopwatch() as watch:
        info = run_info(run_dir)
        protocol = protocol or Protocol()
        policy = load_policy(info, greedy=protocol.greedy, seed=protocol.seed)
        records = evaluate_policy(info.game, policy, protocol, "bench", info.obs, progress=False)
    episodes = sum(record.episodes for record in records)
    steps = sum(sum(record.lengths) for record in records)
    return ProtocolTime(run_dir.name, info.game, episodes, steps, watch.wall, watch.cpu)


def training_command(out_dir: Path, game: str = TRAINING_GAME, frames: int = TRAINING_FRAMES) -> list[str]:
    return [
        sys.executable,
        "-m",
        "gvgai_pcg.cli",
        "train",
        f"game={game}",
        f"total_frames={frames}",
        f"out_dir={out_dir}",
    ]


def training_environment(mode: str, cache_dir: Path) -> dict[str, str]:
    """The child's environment for ``mode``: its own inductor cache (``cold`` and ``warm`` share
    one, in that order), or compiling off (``eager``)."""
    if mode not in TRAINING_MODES:
        raise ValueError(f"unknown training mode {mode!r}; valid ones are: {', '.join(TRAINING_MODES)}")
    env = {**os.environ, "TORCHINDUCTOR_CACHE_DIR": str(cache_dir)}
    env.pop("GVGAI_PCG_COMPILE", None)
    if mode == "eager":
        env["GVGAI_PCG_COMPILE"] = "0"
    return env


def time_training(
    modes: tuple[str, ...] = TRAINING_MODES, frames: int = TRAINING_FRAMES
) -> list[TrainingTime]:
    """Wall seconds of the training command in each of ``modes``, in order, in child processes."""
    times = []
    with tempfile.TemporaryDirectory(prefix="gvgai-pcg-bench-") as folder:
        for mode in modes:
            out_dir = Path(folder) / mode
            with Stopwatch() as watch:
                try:
                    returncode = subprocess.run(
                        training_command(out_dir, frames=frames),
                        env=training_environment(mode, Path(folder) / "inductor"),
                        capture_output=True,
                        timeout=TRAINING_TIMEOUT_S,
                    ).returncode
                except subprocess.TimeoutExpired:  # the child is killed
                    returncode = TIMED_OUT
            times.append(TrainingTime(mode, watch.wall, returncode))
    return times


def protocol_lines(timed: ProtocolTime | None) -> list[str]:
    if timed is None:
        return [
            "",
            "### Evaluation: the protocol on one run",
            "",
            f"No model at {EVALUATED_RUN}: not measured.",
        ]
    return [
        "",
        "### Evaluation: the protocol on one run",
        "",
        f"The study's protocol (30 + 30 generated levels once, 5 human levels x 30 episodes, at most "
        f"2,000 steps, all in one batch) on `{timed.run}` ({timed.game}), from loading the model: "
        f"{timed.wall_s:,.1f} s wall, {timed.cpu_s:,.1f} s CPU; {timed.episodes} episodes, "
        f"{timed.env_steps:,} env steps.",
    ]


def training_lines(times: list[TrainingTime]) -> list[str]:
    by_mode = {t.mode: t for t in times}
    eager = by_mode.get("eager")
    lines = [
        "",
        f"### A {TRAINING_FRAMES:,}-frame training job",
        "",
        f"`gvgai-pcg train game={TRAINING_GAME} total_frames={TRAINING_FRAMES}` (the defaults: PPCG, "
        "tiles, compact net, 64 envs, 1 thread), whole command in a child process: with an empty "
        "inductor cache (cold), again with that cache (warm), and with `GVGAI_PCG_COMPILE=0` (eager).",
        "",
        "| run | wall (s) | / eager |",
        "|---|---:|---:|",
    ]
    for t in times:
        share = ratio(t.wall_s, eager.wall_s) if eager and eager.returncode == 0 else None
        failed = "" if t.returncode == 0 else f" (failed, exit {t.returncode})"
        lines.append(f"| {t.mode}{failed} | {t.wall_s:,.1f} | {'-' if share is None else f'{share:.2f}x'} |")
    return lines


def job_checks(protocol: ProtocolTime | None, training: list[TrainingTime]) -> list[Check]:
    by_mode = {t.mode: t for t in training if t.returncode == 0}
    warm, eager = by_mode.get("warm"), by_mode.get("eager")
    return [
        Check(
            "the study's protocol on one run, wall",
            PROTOCOL_SECONDS,
            protocol.wall_s if protocol else None,
            unit="s",
            at_most=True,
        ),
        Check(
            f"a {TRAINING_FRAMES // 1000}k-frame training job, warm cache / compiling off",
            TRAINING_OVER_EAGER,
            ratio(warm.wall_s, eager.wall_s) if warm and eager else None,
            at_most=True,
        ),
    ]


def jobs_section() -> Section:
    """Both jobs timed, with their targets."""
    protocol = time_protocol() if (EVALUATED_RUN / "model.pt").is_file() else None
    training = time_training()
    text = "\n".join(protocol_lines(protocol) + training_lines(training)) + "\n"
    return Section(text, job_checks(protocol, training))
