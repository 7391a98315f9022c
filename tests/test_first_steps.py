"""What a new user meets first: the docs' first command learns within minutes, the Makefile says
where ``gvgai-pcg`` went, a run keeps one record and leaves a curve even when stopped, a published
run without its model says so, and the cluster settings ask for what a run uses."""

from __future__ import annotations

import json
import os
import re
import signal
from pathlib import Path

import pytest
from omegaconf import OmegaConf

from gvgai_pcg.cli import main
from gvgai_pcg.config import compose_config  # also registers the configs' resolvers
from gvgai_pcg.rl import train
from gvgai_pcg.rundir.run_log import EpisodeTracker

ROOT = Path(__file__).parents[1]
TINY = ["regimen=lv", "env.num_envs=8", "env.max_steps=10", "log.every_episodes=8"]


def _make_run_command() -> str:
    recipe = re.search(
        r"^run: .*\n\t\$\(BIN\)/(gvgai-pcg train [^\n]*)", (ROOT / "Makefile").read_text(), re.M
    )
    return recipe.group(1).replace(" device=cpu", "")


@pytest.mark.parametrize("page", ["docs/index.md", "docs/getting-started.md"])
def test_the_docs_first_training_command_is_the_one_that_learns_within_minutes(page):
    first = re.search(r"^gvgai-pcg train [^#\n]*", (ROOT / page).read_text(), re.M).group(0).strip()
    assert first == _make_run_command()


def test_make_run_says_how_to_put_gvgai_pcg_on_the_path():
    recipe = (ROOT / "Makefile").read_text().split("\nrun: ", 1)[1].split("\n\n", 1)[0]
    assert ". $(VENV)/bin/activate" in recipe
    assert ". .venv/bin/activate" in (ROOT / "README.md").read_text()


def test_the_readme_shows_replay_on_a_published_run_that_has_its_model():
    command = re.search(r"^gvgai-pcg replay (\S+) ", (ROOT / "README.md").read_text(), re.M)
    assert command is not None
    run = ROOT / command.group(1)
    assert (run / "published.json").is_file() and (run / "model.pt").is_file()


def test_replay_of_a_run_published_without_its_model_says_so(tmp_path, capsys):
    published = ROOT / "results/medium/runs/zelda-ppcg-tiles-compact-seed0"
    run = tmp_path / "run"
    run.mkdir()
    (run / "config.yaml").write_text((published / "config.yaml").read_text())
    elsewhere = "/elsewhere/runs/zelda-ppcg-tiles-compact-seed0/model.pt"
    (run / "published.json").write_text(json.dumps({"checkpoint": elsewhere, "frames": 20_000_000}))
    with pytest.raises(SystemExit) as stopped:
        main(["replay", str(run), "--level", "zelda_lvl0", "--out", str(tmp_path / "x.gif")])
    err = capsys.readouterr().err.strip()
    assert stopped.value.code == 2 and len(err.splitlines()) == 1
    assert "its model was not published with it" in err and "No such file" not in err


def test_a_stopped_default_run_leaves_its_curve_and_one_record(tmp_path, monkeypatch):
    batches = {"seen": 0}
    record = EpisodeTracker.update

    def update_then_signal(self, rollout):
        batches["seen"] += 1
        if batches["seen"] == 3:
            os.kill(os.getpid(), signal.SIGTERM)
        return record(self, rollout)

    monkeypatch.setattr(EpisodeTracker, "update", update_then_signal)
    cfg = compose_config([*TINY, "total_frames=4000", f"out_dir={tmp_path}"])
    result = train(cfg, tmp_path / "run")
    assert result.stopped_by == "SIGTERM"
    assert result.curve_path == tmp_path / "run" / "curve.png" and result.curve_path.is_file()
    assert not (tmp_path / "run" / "torchrl").exists()  # log.csv and updates.csv are the record
    assert (tmp_path / "run" / "log.csv").is_file() and (tmp_path / "run" / "updates.csv").is_file()


def test_a_short_runs_curve_shows_its_one_update(tmp_path):
    from gvgai_pcg.rl.curves import curve_figure

    (tmp_path / "log.csv").write_text("frames,episodes,mean_score,difficulty\n")
    (tmp_path / "updates.csv").write_text(
        "frames,updates,policy_loss,value_loss,entropy,fps,time\n320,1,-0.02,0.0003,1.79,1000,0.3\n"
    )
    figure = curve_figure(tmp_path / "log.csv")
    lines = [line for ax in figure.axes for line in ax.get_lines()]
    assert lines and all(
        len(line.get_xdata()) > 1 or line.get_marker() not in ("None", "", None) for line in lines
    )
    assert any("no episode row" in text.get_text() for text in figure.axes[0].texts)


def test_a_slurm_job_asks_for_what_its_run_uses():
    launcher = OmegaConf.load(ROOT / "conf/hydra/launcher/slurm.yaml")
    del launcher["defaults"]
    for threads, workers, cpus, mem_gb in ((1, 1, 1, 2), (2, 3, 6, 6), (0, 1, 1, 2)):
        root = OmegaConf.create({"threads": threads, "collector": {"workers": workers}})
        root.hydra = {"launcher": launcher}
        settings = OmegaConf.to_container(root.hydra.launcher, resolve=True)
        assert (settings["cpus_per_task"], settings["mem_gb"]) == (cpus, mem_gb)


def test_the_sweeps_page_names_submitits_default_preemption_signal():
    page = " ".join((ROOT / "docs/howto/sweeps.md").read_text().split())
    assert "signals its jobs with SIGUSR2" in page and "signals its jobs with SIGUSR1" not in page
