"""Run by ``make extras`` in a fresh venv that holds one optional extra: what the extra is for works,
so an install that "succeeds" with a launcher or logger that cannot run fails here.

``python tests/extras_check.py EXTRA`` exits non-zero, with the reason, when it does not.
"""

from __future__ import annotations

import importlib
import sys
import tempfile

LAUNCHERS = {"slurm": "slurm", "ray": "ray_local", "joblib": "local"}
LOGGERS = ("tensorboard", "wandb")


def check_launcher(launcher: str) -> None:
    """Hydra composes the launcher's config (the plugin's own schema under ours) and resolves it."""
    from hydra import compose, initialize_config_dir
    from omegaconf import OmegaConf

    from gvgai_pcg.config import config_dir

    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        cfg = compose("config", overrides=[f"hydra/launcher={launcher}"], return_hydra_config=True)
    settings = OmegaConf.to_container(cfg.hydra.launcher, resolve=True)
    plugin = settings["_target_"].rsplit(".", 1)
    getattr(importlib.import_module(plugin[0]), plugin[1])
    print(f"hydra/launcher={launcher}: {settings['_target_']}")


def check_logger(name: str) -> None:
    """The run's log mirrors a row to TorchRL's logger of that name."""
    import os
    from pathlib import Path

    os.environ.setdefault("WANDB_MODE", "offline")
    from gvgai_pcg.rundir.run_log import RunLog

    with tempfile.TemporaryDirectory() as tmp:
        log = RunLog(Path(tmp), [name], resume_frames=None)
        log.write({"frames": 40, "episodes": 8, "mean_score": 1.0})
        log.close()
        written = [path for path in Path(tmp).rglob("*") if path.is_file() and path.name != "log.csv"]
        if not any(path.stat().st_size for path in written):
            sys.exit(f"log.backends=[{name}]: the logger wrote nothing beside log.csv")
    print(f"log.backends=[{name}]: a row written ({len(written)} file(s) of the logger's)")


def main(extra: str) -> None:
    if extra in LAUNCHERS:
        check_launcher(LAUNCHERS[extra])
    elif extra in LOGGERS:
        check_logger(extra)
    else:
        sys.exit(f"extras_check: unknown extra {extra!r}; known: {sorted([*LAUNCHERS, *LOGGERS])}")


if __name__ == "__main__":
    main(sys.argv[1])
