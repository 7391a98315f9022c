"""``gvgai-pcg train``: the Hydra app that trains one agent per run (or a sweep with ``-m``).

Configs live in ``conf/`` (groups game, regimen, model, algo, preset, hydra/launcher; a wheel
ships them as ``gvgai_pcg/conf``). Every run of the command line is checked against the schema
(``gvgai_pcg.config``) before Hydra writes any run directory: a bad value ends the command with
one line naming the key, the value and what is allowed. Each run writes its own directory
``out_dir/run_name`` (config, ``log.csv``, checkpoints, ``model.pt``, ``curve.png``); starting
the same command again continues the run from its last checkpoint.

A refusal raised while a run starts (a checkpoint of another config, a run directory in use: any
of the CLI's ``USER_ERRORS``) ends like every other command's, in one line and exit 2, even though
it is raised inside the Hydra app, which would print it as a traceback and exit 1.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from gvgai_pcg.config import CONFIG_NAME, ConfigError, check_jobs, checked_config, config_dir, sweep_jobs


class _Refused(BaseException):
    """Carries a refusal out of the Hydra app: Hydra reports every ``Exception`` of a task
    function itself (a traceback, exit 1) but lets a ``BaseException`` through."""

    def __init__(self, error: BaseException) -> None:
        super().__init__(error)
        self.error = error


def main(cfg) -> None:
    from gvgai_pcg.cli import USER_ERRORS

    try:
        _train(cfg)
    except USER_ERRORS as error:
        raise _Refused(error) from None


def _train(cfg) -> None:
    from hydra.core.hydra_config import HydraConfig

    from gvgai_pcg.rl import train

    # checked again here: a job that check_command_line could not compose (-cd, another sweeper)
    cfg = checked_config(cfg)
    result = train(cfg, Path(HydraConfig.get().runtime.output_dir))
    print(f"run directory: {result.run_dir}")
    print(f"  log:        {result.log_path}")
    print(f"  checkpoint: {result.checkpoint_path} ({result.frames} frames)")
    print(f"  model:      {result.model_path}")
    if result.curve_path is not None:
        print(f"  curve:      {result.curve_path}")


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
    check_jobs(sweep_jobs(args.overrides, args.multirun), args.config_name or CONFIG_NAME)


def run_raw(argv: list[str]) -> int:
    """Hand ``argv`` (Hydra overrides and flags) to the Hydra app, once its runs are checked."""
    import hydra

    try:
        check_command_line(argv)
    except (ConfigError, FileNotFoundError) as error:  # a bad value; configs not installed
        if os.environ.get("GVGAI_PCG_DEBUG"):
            raise
        print(f"gvgai-pcg train: error: {error}", file=sys.stderr)
        return 2
    app = hydra.main(version_base="1.3", config_path=str(config_dir()), config_name=CONFIG_NAME)(main)
    saved_argv = sys.argv
    sys.argv = ["gvgai-pcg train", *argv]
    try:
        app()
    except _Refused as refused:
        raise refused.error from None  # the CLI reports it in one line (GVGAI_PCG_DEBUG=1: traceback)
    finally:
        sys.argv = saved_argv
    return 0
