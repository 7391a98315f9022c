"""A2C trains exactly as it did before learners became plug-ins: a short run's log and weights
are bit-identical to a reference recorded on main at b46ce63 (before the refactor), with and
without the acting graph kept (32 and 8 envs).

Record again (only when A2C's numbers are meant to change) with
``python tests/rl/test_a2c_reference.py --record``.
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
import tempfile
from pathlib import Path

import pytest
import torch

REFERENCE = Path(__file__).parent / "data" / "a2c_reference.json"
CASES = {"keeps_graph": 32, "recomputes": 8}
TIMING_COLUMNS = ("fps", "time")


def _overrides(num_envs: int, out_dir: Path) -> list[str]:
    return [
        "regimen=lv",
        "regimen.level=1",
        f"env.num_envs={num_envs}",
        "env.max_steps=30",
        "total_frames=2400",
        "log.every_episodes=4",
        "log.backends=[]",
        "log.curve=false",
        "checkpoint.every_frames=1000000",
        "threads=1",
        f"out_dir={out_dir}",
    ]


def _digest(tensors: dict) -> str:
    sha = hashlib.sha256()
    for name in sorted(tensors):
        sha.update(name.encode())
        sha.update(tensors[name].detach().cpu().contiguous().numpy().tobytes())
    return sha.hexdigest()


def fingerprint(num_envs: int) -> dict:
    """The log rows (without timings) and the weights' and optimizer's digests of a short run."""
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir
    from gvgai_pcg.rl import train
    from gvgai_pcg.rl.run_log import read_log

    torch.set_num_threads(1)
    with tempfile.TemporaryDirectory() as tmp:
        with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
            cfg = compose("config", overrides=_overrides(num_envs, Path(tmp)))
        result = train(cfg, Path(tmp) / cfg.run_name)
        rows = [
            {k: "nan" if math.isnan(v) else v for k, v in row.items() if k not in TIMING_COLUMNS}
            for row in read_log(result.log_path)
        ]
        checkpoint = torch.load(result.checkpoint_path, weights_only=False)
        optimizer = {
            f"{index}.{key}": value
            for index, state in checkpoint["optimizer"]["state"].items()
            for key, value in state.items()
            if isinstance(value, torch.Tensor)
        }
        return {
            "frames": result.frames,
            "rows": rows,
            "model": _digest(checkpoint["model"]),
            "optimizer": _digest(optimizer),
        }


@pytest.mark.parametrize(
    "case",
    ["keeps_graph", pytest.param("recomputes", marks=pytest.mark.slow)],  # the study's 12 envs' path
)
def test_a2c_is_bit_identical_to_the_reference(case):
    expected = json.loads(REFERENCE.read_text())[case]
    found = json.loads(json.dumps(fingerprint(CASES[case])))  # the floats as the file keeps them
    assert found["frames"] == expected["frames"]
    assert found["rows"] == expected["rows"]
    assert found["model"] == expected["model"], "the weights differ from the reference"
    assert found["optimizer"] == expected["optimizer"], "the RMSprop state differs from the reference"


if __name__ == "__main__" and "--record" in sys.argv:
    REFERENCE.write_text(json.dumps({case: fingerprint(n) for case, n in CASES.items()}, indent=1) + "\n")
    print(f"wrote {REFERENCE}")
