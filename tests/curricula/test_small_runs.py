"""The published ``small`` runs train, resume and evaluate as before the regimens became
registered curricula: each run's config.yaml composes again to the same resolved config, and its
regimen builds the same level source (the same levels for the same seeds), shared state and
training set as the code of main at b46ce63 did (``data/small_runs_today.json``, written by
``data/record_small_runs.py`` on that commit)."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest
import torch
import yaml
from omegaconf import OmegaConf

from gvgai_pcg.config import compose_config, validate
from gvgai_pcg.rl.environment import curriculum_run, training_levels, training_source
from gvgai_pcg.rundir.checkpoint import config_differences

ROOT = Path(__file__).resolve().parents[2]
RUNS = sorted((ROOT / "results" / "small" / "runs").glob("*/config.yaml"))
TODAY = json.loads((Path(__file__).parent / "data" / "small_runs_today.json").read_text())


def _saved(path: Path) -> dict:
    return yaml.safe_load(path.read_text())


def test_every_small_run_was_recorded():
    assert len(RUNS) == len(TODAY) == 36
    assert {path.parent.name for path in RUNS} == set(TODAY)


@pytest.mark.parametrize("path", RUNS, ids=lambda path: path.parent.name)
def test_the_regimen_builds_what_it_built_before(path):
    saved, today = _saved(path), TODAY[path.parent.name]
    game, regimen = saved["game"]["name"], OmegaConf.create(saved["regimen"])
    source = training_source(game, regimen)
    levels = source.next_levels(
        torch.arange(6),
        torch.tensor([0, 1, 7, 2**31 + 5, 123456789, 3], dtype=torch.int64),
        torch.tensor([0.0, 0.25, 0.5, 0.75, 1.0, 0.3], dtype=torch.float64),
    )
    text = "\n\n".join("\n".join(lv.rows) + f"|{lv.name}|{lv.seed}" for lv in levels)
    trained = training_levels(game, regimen)
    assert repr(source) == today["source"]
    assert hashlib.sha256(text.encode()).hexdigest() == today["levels_sha256"]
    assert source.prepare_ahead == today["prepare_ahead"]
    assert source.depends_on_difficulty == today["depends_on_difficulty"]
    assert repr(curriculum_run(regimen, game).state) == today["state"]
    assert (None if trained is None else [lv.name for lv in trained]) == today["training_levels"]
    # bookkeeping keys added since the small runs were trained (they may change on resume)
    added = {
        "checkpoint": {**saved["checkpoint"], "keep_every_frames": 0},
        "log": {"every_update_frames": 10_000, **saved["log"]},
    }
    checked = validate({**saved, **added})
    assert checked["regimen"] == today["validated_regimen"] == saved["regimen"]


# One run of each condition (the seeds differ in ``seed`` only): composed again from its group
# options and values, it is the config the run was made with (what resuming compares).
CONDITIONS = [path for path in RUNS if path.parent.name.endswith("seed0")]


@pytest.mark.parametrize("path", CONDITIONS, ids=lambda path: path.parent.name)
def test_the_config_composes_again_to_the_run_config(path):
    saved = _saved(path)
    regimen = saved["regimen"]
    overrides = [f"game={saved['game']['name']}", f"regimen={regimen['name']}"]
    overrides += [f"regimen.{key}={json.dumps(value)}" for key, value in regimen.items() if key != "tag"]
    for section in ("model", "algo", "env", "collector", "checkpoint", "log"):
        overrides += [f"{section}.{key}={json.dumps(value)}" for key, value in saved[section].items()]
    overrides += [f"{key}={saved[key]}" for key in ("seed", "total_frames", "device", "threads", "out_dir")]
    composed = OmegaConf.to_container(compose_config(overrides), resolve=True)
    assert config_differences(saved, composed) == []
    assert composed["run_name"] == path.parent.name
