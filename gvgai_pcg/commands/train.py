"""``gvgai-pcg train``: the Hydra app that trains one agent per run (or a sweep with ``-m``).

Configs live in ``conf/`` (groups game, regimen, model, algo, preset, hydra/launcher). Each run
writes its own directory ``out_dir/run_name`` (config, ``log.csv``, checkpoints, ``model.pt``,
``curve.png``); starting the same command again continues the run from its last checkpoint.
"""

from __future__ import annotations

import sys
from pathlib import Path

CONFIG_DIR = Path(__file__).resolve().parents[2] / "conf"


def main(cfg) -> None:
    from hydra.core.hydra_config import HydraConfig

    from gvgai_pcg.rl import train

    result = train(cfg, Path(HydraConfig.get().runtime.output_dir))
    print(f"run directory: {result.run_dir}")
    print(f"  log:        {result.log_path}")
    print(f"  checkpoint: {result.checkpoint_path} ({result.frames} frames)")
    print(f"  model:      {result.model_path}")
    if result.curve_path is not None:
        print(f"  curve:      {result.curve_path}")


def run_raw(argv: list[str]) -> int:
    """Hand ``argv`` (Hydra overrides and flags) to the Hydra app."""
    import hydra

    if not CONFIG_DIR.is_dir():
        raise SystemExit(f"the Hydra configs are missing: expected them in {CONFIG_DIR}")
    app = hydra.main(version_base="1.3", config_path=str(CONFIG_DIR), config_name="config")(main)
    saved_argv = sys.argv
    sys.argv = ["gvgai-pcg train", *argv]
    try:
        app()
    finally:
        sys.argv = saved_argv
    return 0
