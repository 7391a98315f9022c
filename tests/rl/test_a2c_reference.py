"""A2C trains as it did before learners became plug-ins: a short run's log and weights match a
reference recorded on main at b46ce63 (before the refactor), with and without the acting graph
kept (32 and 8 envs).

They match to a relative tolerance, not bit for bit: the CPU's matrix kernels (AVX2 or AVX-512,
one thread or two) sum in different orders, which moves the weights by about 5e-6 of their norm
after this run; a 5% larger entropy coefficient moves them by 1e-2, so ``RTOL`` (2e-4) holds on
any x86 CPU and still catches a real change (``test_a_small_change_to_a2c_fails_the_reference``).
The reference keeps, per tensor, its norm and four projections on fixed random signs, so a
change anywhere in a tensor shows.

Record again (only when A2C's numbers are meant to change) with
``python tests/rl/test_a2c_reference.py --record``.
"""

from __future__ import annotations

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
RTOL = 2e-4  # of a tensor's norm, and of a logged value
ATOL = 1e-7  # a logged value near 0 (a loss that is a difference of nearly equal terms)
PROJECTIONS = 4


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


def _statistics(tensors: dict) -> dict:
    """Per tensor: its shape, norm and projections on fixed random signs (the same on any CPU)."""
    found = {}
    for name in sorted(tensors):
        values = tensors[name].detach().cpu().double().flatten()
        signs = torch.randint(0, 2, (PROJECTIONS, values.numel()), generator=torch.Generator().manual_seed(0))
        found[name] = {
            "shape": list(tensors[name].shape),
            "norm": values.norm().item(),
            "projections": ((signs * 2 - 1).double() @ values).tolist(),
        }
    return found


def fingerprint(num_envs: int, extra: tuple[str, ...] = ()) -> dict:
    """The log rows (without timings) and the weights' and optimizer's statistics of a short run."""
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir
    from gvgai_pcg.rl import train
    from gvgai_pcg.rundir.run_log import read_log

    torch.set_num_threads(1)
    with tempfile.TemporaryDirectory() as tmp:
        with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
            keys = {item.split("=")[0] for item in extra}  # ``extra`` replaces what it names
            base = [item for item in _overrides(num_envs, Path(tmp)) if item.split("=")[0] not in keys]
            cfg = compose("config", overrides=[*base, *extra])
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
            "model": _statistics(checkpoint["model"]),
            "optimizer": _statistics(optimizer),
        }


def differences(found: dict, expected: dict) -> list[str]:
    """What differs beyond the tolerance between two fingerprints, one line each."""
    if found["frames"] != expected["frames"] or len(found["rows"]) != len(expected["rows"]):
        return [
            f"{found['frames']} frames in {len(found['rows'])} rows, expected {expected['frames']} frames"
        ]
    diffs = []
    for index, (row, old) in enumerate(zip(found["rows"], expected["rows"], strict=True)):
        for key, value in old.items():
            new = row.get(key)
            same = new == value if isinstance(value, str) or isinstance(new, str) else None
            if not (same if same is not None else math.isclose(new, value, rel_tol=RTOL, abs_tol=ATOL)):
                diffs.append(f"row {index} {key}: {new!r}, expected {value!r}")
    for part in ("model", "optimizer"):
        if found[part].keys() != expected[part].keys():
            diffs.append(f"{part}: tensors {sorted(found[part])}, expected {sorted(expected[part])}")
            continue
        for name, old in expected[part].items():
            new, scale = found[part][name], RTOL * old["norm"]
            if new["shape"] != old["shape"]:
                diffs.append(f"{part} {name}: shape {new['shape']}, expected {old['shape']}")
                continue
            pairs = zip([new["norm"], *new["projections"]], [old["norm"], *old["projections"]], strict=True)
            worst = max(abs(a - b) for a, b in pairs)
            if worst > scale:
                diffs.append(
                    f"{part} {name}: off by {worst / old['norm']:.2g} of its norm (tolerance {RTOL:g})"
                )
    return diffs


@pytest.mark.parametrize(
    "case",
    ["keeps_graph", pytest.param("recomputes", marks=pytest.mark.slow)],  # the study's 12 envs' path
)
def test_a2c_matches_the_reference(case):
    expected = json.loads(REFERENCE.read_text())[case]
    found = json.loads(json.dumps(fingerprint(CASES[case])))  # the floats as the file keeps them
    assert differences(found, expected) == []


def test_a_small_change_to_a2c_fails_the_reference():
    """The tolerance is no blind spot: a 5% larger entropy coefficient (0.0105) is caught."""
    expected = json.loads(REFERENCE.read_text())["keeps_graph"]
    found = fingerprint(CASES["keeps_graph"], ("algo.entropy_coef=0.0105",))
    diffs = differences(found, expected)
    assert any(line.startswith("model ") for line in diffs), diffs


def test_the_tolerance_absorbs_another_summation_order():
    """Two threads sum the matrix products in another order than one, as another CPU's kernels
    do: the run still matches."""
    before = torch.get_num_threads()
    try:
        expected = json.loads(REFERENCE.read_text())["keeps_graph"]
        found = json.loads(json.dumps(fingerprint(CASES["keeps_graph"], ("threads=2",))))
        assert differences(found, expected) == []
    finally:
        torch.set_num_threads(before)


if __name__ == "__main__" and "--record" in sys.argv:
    REFERENCE.write_text(json.dumps({case: fingerprint(n) for case, n in CASES.items()}, indent=1) + "\n")
    print(f"wrote {REFERENCE}")
