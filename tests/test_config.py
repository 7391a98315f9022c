"""The training config's schema: a bad value stops ``gvgai-pcg train`` before any run directory is
written, in one line that names the key, the value and what is allowed."""

from __future__ import annotations

import itertools
import subprocess
import sys

import pytest
from omegaconf import OmegaConf

from gvgai_pcg.cli import main
from gvgai_pcg.config import ConfigError, check_jobs, compose_config, config_dir, sweep_jobs, validate
from tests.waiting import PATIENCE_S


def refusal(argv: list[str], capsys, tmp_path) -> str:
    """Run ``gvgai-pcg train ARGV`` and return its one-line error; nothing may be written."""
    out = tmp_path / "runs"
    assert main(["train", *argv, f"out_dir={out}"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()
    assert err.startswith("gvgai-pcg train: error: ")
    return err.removeprefix("gvgai-pcg train: error: ").strip()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["total_frames=-5"], "total_frames=-5: expected an integer >= 1"),
        (["algo.lr=abc"], "algo.lr='abc': expected a finite number > 0"),
        (["algo.lr=inf"], "algo.lr=inf: expected a finite number > 0"),
        (["algo.lr=0"], "algo.lr=0: expected a finite number > 0"),
        (["env.num_envs=0"], "env.num_envs=0: expected an integer >= 1"),
        (["env.num_envs=2.5"], "env.num_envs=2.5: expected an integer >= 1"),
        (["env.obs=rgb"], "env.obs='rgb': expected one of tiles, pixels"),
        (["algo.gamma=1.5"], "algo.gamma=1.5: expected a number in [0, 1]"),
        (["regimen=pcg", "regimen.difficulty=-0.1"], "regimen.difficulty=-0.1: expected a number in [0, 1]"),
        (["regimen=ppcg", "regimen.alpha=0"], "regimen.alpha=0: expected a number in (0, 1]"),
        (
            ["regimen=ppcg", "regimen.win_rule=always"],
            "regimen.win_rule='always': expected one of game, study",
        ),
        (["regimen=lv", "regimen.level=5"], "regimen.level=5: expected an integer in [0, 4]"),
        (
            ["regimen=pcg", "regimen.num_levels=-1"],
            "regimen.num_levels=-1: expected an integer in [0, 2147483648]",
        ),
        (["seed=-1"], "seed=-1: expected an integer in [0, 4294967295]"),
        (["log.curve=maybe"], "log.curve='maybe': expected true or false"),
        (["log.backends=[csv,mlflow]"], "log.backends=['csv', 'mlflow']: expected a list without repeats"),
        (["collector.workers=0"], "collector.workers=0: expected an integer >= 1"),
        (["checkpoint.every_frames=0"], "checkpoint.every_frames=0: expected an integer >= 1"),
        (["device=cuda:7"], "device='cuda:7': expected cpu, cuda, cuda:N or mps, present on this machine"),
        (["model=nature"], "env.obs='tiles': expected pixels with model=nature"),
        (["foo=1"], "foo=1: unknown key; the keys of the config are game, regimen"),
        (["regimen.foo=2"], "regimen.foo=2: unknown key; the keys of regimen are name, alpha"),
        (["+algo.momentum=0.9"], "algo.momentum=0.9: unknown key; the keys of algo are name, n_steps"),
        (["regimen=levels"], "regimen.path: missing (???); expected a folder of level files"),
        (["run_name=${nope}"], "run_name: does not resolve (Interpolation key 'nope' not found)"),
        (
            ["regimen=pcg", "regimen.start_seed=3"],
            "regimen.start_seed=3: expected 0 with regimen.num_levels=0 (unlimited levels)",
        ),
    ],
)
def test_a_bad_value_is_refused_in_one_line_before_the_run_starts(argv, message, capsys, tmp_path):
    assert refusal(argv, capsys, tmp_path).startswith(message)


def test_every_run_of_a_sweep_is_checked_before_any_starts(capsys, tmp_path):
    err = refusal(["-m", "seed=0,1", "algo.lr=0.001,abc"], capsys, tmp_path)
    assert err == "algo.lr='abc': expected a finite number > 0"


@pytest.mark.parametrize(
    "hydra_setting",
    ["hydra.no_such_key=1", "hydra.launcher.timeout_min=10", "hydra/launcher=no_such_launcher"],
)
def test_a_hydra_setting_that_does_not_compose_here_still_has_every_run_checked(hydra_setting):
    """Before Hydra starts a sweep: its second run's bad value is refused with Hydra's own setting
    on the line (Hydra judges that setting itself), not after the first run has trained."""
    from gvgai_pcg.commands.train import check_command_line

    with pytest.raises(ConfigError, match=r"^algo\.lr=-1: expected a finite number > 0$"):
        check_command_line(["-m", hydra_setting, "algo.lr=0.001,-1"])


def test_debug_shows_the_traceback(tmp_path):
    command = [sys.executable, "-m", "gvgai_pcg.cli", "train", f"out_dir={tmp_path}", "algo.lr=abc"]
    done = subprocess.run(
        command, capture_output=True, text=True, timeout=PATIENCE_S, env={"GVGAI_PCG_DEBUG": "1"}
    )
    assert done.returncode != 0 and "Traceback" in done.stderr and "ConfigError: algo.lr='abc'" in done.stderr


def test_a_level_set_with_a_bad_file_names_its_file_line_and_column(tmp_path, capsys):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "a.txt").write_text("wwwww\nwA+gw\nwwwww\n")
    (folder / "b.txt").write_text("wwwww\nwA+gw\nww?ww\n")
    err = refusal(["regimen=levels", f"regimen.path={folder}"], capsys, tmp_path)
    assert f"{folder / 'b.txt'}, line 3, column 3: character '?' is not in the zelda legend" in err


def test_integral_floats_are_integers_and_level_paths_absolute(tmp_path, monkeypatch):
    (tmp_path / "zelda_a.txt").write_text("wwwww\nwA+gw\nwwwww\n")
    monkeypatch.chdir(tmp_path)
    cfg = compose_config(["total_frames=1e6", "regimen=levels", "regimen.path=zelda_a.txt"])
    assert cfg.total_frames == 1_000_000 and isinstance(cfg.total_frames, int)
    assert cfg.regimen.path == str(tmp_path / "zelda_a.txt")
    assert cfg.run_name == "zelda-levels-zelda_a-tiles-compact-seed0"


def test_every_shipped_combination_is_valid():
    games, models = (
        ("zelda", "solarfox", "frogs", "boulderdash"),
        (("compact", "tiles"), ("nature", "pixels")),
    )
    regimens = ("lv", "lv0-3", "pcg", "ppcg")
    jobs = [
        [f"game={g}", f"regimen={r}", f"model={m}", f"env.obs={o}", *p]
        for g, r, (m, o), p in itertools.product(games, regimens, models, ([], ["preset=paper"]))
    ]
    assert check_jobs(jobs)


def test_a_sweep_expands_into_its_runs():
    assert sweep_jobs(["seed=0,1", "regimen.num_levels=10,100"], multirun=True) == [
        ["seed=0", "regimen.num_levels=10"],
        ["seed=0", "regimen.num_levels=100"],
        ["seed=1", "regimen.num_levels=10"],
        ["seed=1", "regimen.num_levels=100"],
    ]
    assert sweep_jobs(["seed=0,1"], multirun=False) == [["seed=0,1"]]


def test_a_plain_dict_is_checked_too():
    config = OmegaConf.to_container(compose_config())
    with pytest.raises(ConfigError, match=r"^env: missing; expected a section"):
        validate({key: value for key, value in config.items() if key != "env"})


def test_the_configs_are_found():
    assert (config_dir() / "config.yaml").is_file() and (config_dir() / "regimen" / "levels.yaml").is_file()
