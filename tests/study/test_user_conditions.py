"""A user's own conditions join the comparison: a curriculum plug-in's (its condition with each
game, ``<game>-<name>``) and those of a config folder of their own (``--config-dir DIR``:
``DIR/condition/<name>.yaml``), planned by ``reproduce``, composed and trained by ``train``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from gvgai_pcg.cli import main
from gvgai_pcg.config import compose_config
from gvgai_pcg.config_rules import searchpath_dirs, searchpath_override
from gvgai_pcg.curricula import register_curriculum, registry
from gvgai_pcg.study.sweeps.conditions import condition_regimen, unregistered, user_conditions
from tests.curricula import toy_curriculum

ROOT = Path(__file__).resolve().parents[2]
SMALL = ["env.num_envs=4", "env.max_steps=6", "log.every_episodes=4", "log.curve=false"]
# Frogs' PCG at d = 0.3: a condition that is in no yaml of the package
MINE = """# @package _global_
defaults:
  - override /game: frogs
  - override /regimen: pcg
regimen:
  difficulty: 0.3
"""


@pytest.fixture
def toy(monkeypatch):
    """The toy curriculum registered for one test (ticks eager: a short run would compile)."""
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    register_curriculum(toy_curriculum.CURRICULUM)
    yield toy_curriculum.CURRICULUM
    registry.unregister_curriculum("toyreplay")


@pytest.fixture
def mine(tmp_path) -> Path:
    """A config folder of the user's own with one condition, ``frogs-pcg0.3``."""
    folder = tmp_path / "myconf"
    (folder / "condition").mkdir(parents=True)
    (folder / "condition" / "frogs-pcg0.3.yaml").write_text(MINE)
    return folder


def test_a_plugin_curriculum_is_a_condition_with_every_game(toy):
    assert {"zelda-toyreplay", "frogs-toyreplay"} <= set(user_conditions())
    assert not {"zelda-plr", "zelda-ppcg"} & set(user_conditions())  # ours are the package's
    assert condition_regimen("zelda-toyreplay") == "toyreplay" and not unregistered(["zelda-toyreplay"])
    cfg = compose_config(["condition=zelda-toyreplay", *SMALL])
    assert (cfg.game.name, cfg.regimen.name) == ("zelda", "toyreplay")


def test_a_config_folder_s_conditions_are_found_through_the_searchpath(mine):
    override = searchpath_override(mine)
    assert searchpath_dirs(["seed=0", override]) == (mine.resolve(),)
    assert user_conditions([mine]) == ("frogs-pcg0.3",)
    assert condition_regimen("frogs-pcg0.3", [mine]) == "pcg"
    with pytest.raises(ValueError, match="unknown condition 'frogs-pcg0.3': no frogs-pcg0.3.yaml in"):
        condition_regimen("frogs-pcg0.3")
    cfg = compose_config([override, "condition=frogs-pcg0.3", *SMALL])
    assert (cfg.game.name, cfg.regimen.name, cfg.regimen.difficulty) == ("frogs", "pcg", 0.3)


def test_reproduce_plans_a_plugin_s_condition_and_a_config_folder_s(toy, mine, tmp_path, capsys):
    out = tmp_path / "sweep"
    common = ["reproduce", "--budget", "curricula-smoke", "--status", "--out", str(out)]
    assert main([*common, "--conditions", "zelda-toyreplay,zelda-ppcg"]) == 0
    assert "zelda-toyreplay4-tiles-compact-seed0" in capsys.readouterr().out
    assert main([*common, "--config-dir", str(mine), "--conditions", "frogs-pcg0.3,zelda-toyreplay"]) == 0
    planned = capsys.readouterr().out
    assert "frogs-pcg0.3-tiles-compact-seed0" in planned and "zelda-toyreplay4-" in planned
    with pytest.raises(SystemExit) as refused:
        main([*common, "--config-dir", str(tmp_path), "--conditions", "frogs-pcg0.3"])
    assert refused.value.code == 2 and "no condition/ folder in it" in capsys.readouterr().err


def test_train_takes_a_user_s_conditions_in_a_sweep(toy, mine, tmp_path):
    """What ``reproduce`` starts for them: ``gvgai-pcg train -m condition=...`` with the searchpath."""
    from gvgai_pcg.commands.train import run_raw

    conditions = "condition=zelda-toyreplay,frogs-pcg0.3"
    argv = ["-m", conditions, searchpath_override(mine), "total_frames=48", f"out_dir={tmp_path}", *SMALL]
    assert run_raw(argv) == 0
    trained = {path.parent.name for path in tmp_path.glob("*/model.pt")}
    assert trained == {"zelda-toyreplay4-tiles-compact-seed0", "frogs-pcg0.3-tiles-compact-seed0"}


ENTRY_POINTS = "[gvgai_pcg.curricula]\ntoyreplay = tests.curricula.toy_curriculum:CURRICULUM\n"


@pytest.mark.slow
def test_a_plugin_s_curriculum_joins_the_curricula_comparison_end_to_end(tmp_path):
    """An installed plug-in (an entry point of a distribution on the path) trained, evaluated
    with both protocols and compared with PPCG by ``reproduce --budget curricula-smoke``."""
    dist = tmp_path / "site" / "toy_pkg-0.1.dist-info"
    dist.mkdir(parents=True)
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: toy-pkg\nVersion: 0.1\n")
    (dist / "entry_points.txt").write_text(ENTRY_POINTS)
    path = os.pathsep.join([str(tmp_path / "site"), str(ROOT), os.environ.get("PYTHONPATH", "")])
    env = {**os.environ, "PYTHONPATH": path, "GVGAI_PCG_COMPILE": "0"}
    out = tmp_path / "sweep"
    command = [sys.executable, "-m", "gvgai_pcg.cli", "reproduce", "--budget", "curricula-smoke"]
    command += ["--conditions", "zelda-toyreplay,zelda-ppcg", "--out", str(out), "--no-progress"]
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-2000:]
    page = (out / "report" / "curricula.md").read_text()
    assert "| Toy replay | 1 | 800 |" in page and "Toy replay beats PPCG" in page
    records = list((out / "runs" / "zelda-toyreplay4-tiles-compact-seed0" / "eval").glob("ued-*.json"))
    assert records and json.loads(records[0].read_text())["summary"]["levels"] == 8
