"""``gvgai-pcg train``: the Hydra app that trains one agent per run (or a sweep with ``-m``).

Configs live in ``conf/`` (groups game, regimen, model, algo, preset, hydra/launcher; a wheel
ships them as ``gvgai_pcg/conf``). Every run of the command line is checked against the schema
(``gvgai_pcg.config``) before Hydra writes any run directory: a bad value ends the command with
one line naming the key, the value and what is allowed. Each run writes its own directory
``out_dir/run_name`` (config, ``log.csv``, checkpoints, ``model.pt``, ``curve.png``); starting
the same command again continues the run from its last checkpoint.

A refusal raised while a run starts (a checkpoint of another config, a run directory in use: any
of the CLI's ``USER_ERRORS``) ends like every other command's, in one line and exit 2, even though
it is raised inside the Hydra app, which would print it as a traceback and exit 1. A run stopped
by SIGINT or SIGTERM says in one line where it stopped and how to resume, and exits 130 or 143; a
diverged run says at what frames and which quantity, and exits 3. A run stopped by anything else
(a write to a closed pipe or a full disk, a logger backend that fails, a second Ctrl-C) has its
last complete update saved by the session; it says so in one line, on whichever of stderr,
stdout or ``train.log`` can still be written, and exits non-zero (141 for a closed pipe).

Hydra is told not to write ``.hydra/`` itself (``hydra.output_subdir: null``): it would do so
before the task function runs, so a resume that is then refused would already have overwritten
the run's ``.hydra/config.yaml`` and ``overrides.yaml``. The task function hands the same three
files to ``train``, which writes them once the session is accepted.
"""

from __future__ import annotations

import logging
import os
import shlex
import signal
import sys
from pathlib import Path

from gvgai_pcg.cli import USER_ERRORS, say
from gvgai_pcg.commands.train_checks import check_argv
from gvgai_pcg.config import CONFIG_NAME, check_jobs, checked_config, config_dir, sweep_jobs

_STOP = None  # the StopSignal that run_raw installs for the whole command (none in a launcher's job)


class _Refused(BaseException):
    """Carries a refusal out of the Hydra app: Hydra reports every ``Exception`` of a task
    function itself (a traceback, exit 1) but lets a ``BaseException`` through."""

    def __init__(self, error: BaseException) -> None:
        super().__init__(error)
        self.error = error


def main(cfg) -> None:
    try:
        _train(cfg)
    except USER_ERRORS as error:
        raise _Refused(error) from None


def _train(cfg) -> None:
    from hydra.core.hydra_config import HydraConfig

    from gvgai_pcg.rl import train
    from gvgai_pcg.rl.divergence import DivergenceError
    from gvgai_pcg.rl.run_session import TrainingStopped
    from gvgai_pcg.rundir.stop_signal import StopSignal

    files = _hydra_files(cfg)
    # checked again here: a job that check_command_line could not compose (-cd, another sweeper)
    cfg = checked_config(cfg)
    hydra, stop = HydraConfig.get(), _STOP or StopSignal()
    again = " ".join(["gvgai-pcg train", *map(shlex.quote, hydra.overrides.task)])
    try:
        result = train(cfg, Path(hydra.runtime.output_dir), files=files, stop=stop)
    except DivergenceError as error:
        _tell(f"gvgai-pcg train: {error}")
        raise SystemExit(3) from None
    except TrainingStopped as error:
        if os.environ.get("GVGAI_PCG_DEBUG"):
            raise
        after = f" (after {stop.name})" if stop.received else ""
        _tell(f"gvgai-pcg train: {error}{after}; resume with: {again}")
        if stop.received:
            stop.hand_over()
        raise SystemExit(_stopped_exit_code(error, stop)) from None
    if result.stopped_by:
        _tell(
            f"gvgai-pcg train: stopped by {result.stopped_by} at {result.frames} frames, checkpoint "
            f"{result.checkpoint_path}; resume with: {again}"
        )
        stop.hand_over()  # a launcher's own handlers (submitit requeues the job here)
        raise SystemExit(stop.exit_code)
    print(f"run directory: {result.run_dir}")
    print(f"  log:        {result.log_path}")
    print(f"  updates:    {result.updates_path}")
    print(f"  checkpoint: {result.checkpoint_path} ({result.frames} frames)")
    print(f"  model:      {result.model_path}")
    if result.curve_path is not None:
        print(f"  curve:      {result.curve_path}")


def _tell(line: str) -> None:
    """``line`` on stderr, else stdout, else only in the run's ``train.log`` (Hydra's file handler):
    a stop through a pipe whose reader died still says where it stopped."""
    if not say(line):
        logging.getLogger(__name__).error(line)


def _stopped_exit_code(error, stop) -> int:
    """The shell's code of what stopped the run: the signal received (130, 143), a second Ctrl-C
    (130), a write to a closed pipe (141, as if SIGPIPE had ended it), anything else 1."""
    if stop.received:
        return stop.exit_code
    if isinstance(error.cause, KeyboardInterrupt):
        return 128 + signal.SIGINT
    if isinstance(error.cause, BrokenPipeError):
        return 128 + signal.SIGPIPE
    return 1


def _hydra_files(cfg) -> dict[str, str]:
    """What Hydra writes to ``.hydra/`` when ``hydra.output_subdir`` is set, as name -> text."""
    from hydra.core.hydra_config import HydraConfig
    from omegaconf import OmegaConf

    hydra_cfg = HydraConfig.instance().cfg
    return {
        ".hydra/config.yaml": OmegaConf.to_yaml(cfg),
        ".hydra/hydra.yaml": OmegaConf.to_yaml(hydra_cfg),
        ".hydra/overrides.yaml": OmegaConf.to_yaml(hydra_cfg.hydra.overrides.task),
    }


class _NotParsed(Exception):
    pass


def check_command_line(argv: list[str]) -> None:
    """Check the config of every run ``argv`` starts, before Hydra starts any (``ConfigError``).
    A command line that starts no run (``--help``, ``--cfg``), or whose configs come from
    elsewhere (``-cp``, ``-cd``), is left to Hydra."""
    from hydra._internal.utils import get_args_parser

    parser = get_args_parser()

    def refuse(message: str) -> None:
        raise _NotParsed(message)

    parser.error = refuse  # Hydra reports its own usage errors when it parses argv
    try:
        args = parser.parse_args(argv)
    except _NotParsed:
        return
    if any((args.help, args.hydra_help, args.info, args.cfg, args.shell_completion, args.experimental_rerun)):
        return
    if args.config_path or args.config_dir:
        return
    check_jobs(sweep_jobs(args.overrides, args.multirun or _multirun_by_override(args.overrides)),
               args.config_name or CONFIG_NAME)  # fmt: skip


def _multirun_by_override(overrides: list[str]) -> bool:
    """Whether ``hydra.mode=MULTIRUN`` makes a sweep of the command line without ``-m``."""
    return any(
        key.lstrip("+") == "hydra.mode" and value.strip().upper() == "MULTIRUN"
        for key, _, value in (override.partition("=") for override in overrides)
    )


class _StoppedWhileStarting(BaseException):
    """SIGTERM outside the training session (imports, config, the final files): nothing to save."""


def _stopped_while_starting(signum: int, frame: object) -> None:
    raise _StoppedWhileStarting


def run_raw(argv: list[str]) -> int:
    """Hand ``argv`` (Hydra overrides and flags) to the Hydra app, once its runs are checked."""
    global _STOP
    original = signal.getsignal(signal.SIGTERM)
    if original is signal.SIG_DFL:  # torch and Hydra take seconds to import
        signal.signal(signal.SIGTERM, _stopped_while_starting)
    try:
        try:
            check_argv(argv, config_dir())  # a missing option or package: before Hydra and torch
            import hydra

            from gvgai_pcg.rundir.stop_signal import StopSignal

            check_command_line(argv)
        except (ValueError, FileNotFoundError) as error:  # a bad value; configs not installed
            if os.environ.get("GVGAI_PCG_DEBUG"):
                raise
            print(f"gvgai-pcg train: error: {error}", file=sys.stderr)
            return 2
        app = hydra.main(version_base="1.3", config_path=str(config_dir()), config_name=CONFIG_NAME)(main)
        signal.signal(signal.SIGTERM, original)
        saved_argv, _STOP = sys.argv, StopSignal(outside_training=_StoppedWhileStarting).install()
        sys.argv = ["gvgai-pcg train", *argv]
        try:
            app()
        except _Refused as refused:
            raise refused.error from None  # the CLI reports it in one line (GVGAI_PCG_DEBUG=1: traceback)
        finally:
            sys.argv = saved_argv
            _STOP.uninstall()
            _STOP = None
    except _StoppedWhileStarting:
        sys.stderr.write("gvgai-pcg train: stopped by SIGTERM outside the training loop (nothing to save)\n")
        return 128 + signal.SIGTERM
    finally:
        signal.signal(signal.SIGTERM, original)
    return 0
