"""Record, with the code of main, each small run's level source and shared state, as a fixture."""

import hashlib
import json
import sys
from pathlib import Path

import torch
import yaml
from omegaconf import OmegaConf

from gvgai_pcg.config import validate
from gvgai_pcg.rl.environment import curriculum_run, training_levels, training_source

root = Path(sys.argv[1])
out = {}
for run in sorted((root / "results/small/runs").iterdir()):
    saved = yaml.safe_load((run / "config.yaml").read_text())
    game = saved["game"]["name"]
    regimen = OmegaConf.create(saved["regimen"])
    source = training_source(game, regimen)
    envs = torch.arange(6)
    seeds = torch.tensor([0, 1, 7, 2**31 + 5, 123456789, 3], dtype=torch.int64)
    ds = torch.tensor([0.0, 0.25, 0.5, 0.75, 1.0, 0.3], dtype=torch.float64)
    levels = source.next_levels(envs, seeds, ds)
    digest = hashlib.sha256(
        "\n\n".join("\n".join(l.rows) + f"|{l.name}|{l.seed}" for l in levels).encode()
    ).hexdigest()
    state = curriculum_run(regimen, game).state
    train = training_levels(game, regimen)
    out[run.name] = {
        "source": repr(source),
        "prepare_ahead": source.prepare_ahead,
        "depends_on_difficulty": source.depends_on_difficulty,
        "levels_sha256": digest,
        "state": repr(state),
        "training_levels": None if train is None else [l.name for l in train],
        "validated_regimen": validate(
            {**saved, "checkpoint": {**saved["checkpoint"], "keep_every_frames": 0}}
        )["regimen"],
    }
print(json.dumps(out, indent=1, sort_keys=True))
