"""Evaluation plays a model only when it is safe to load, finite, and the run's own model; one
process at a time writes a run's results, the random agent's cache and a report folder."""

from __future__ import annotations

import fcntl
import logging
import math
import os
from pathlib import Path

import pytest
import torch

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.evaluator import random_results_path, run_results_path, write_records
from gvgai_pcg.evaluation.protocol import Protocol
from gvgai_pcg.report import build_report
from gvgai_pcg.rundir.checkpoint import save_model
from tests.evaluation.conftest import make_run
from tests.evaluation.test_report import PROTOCOL, fake_records

FAST = ["--test-levels", "1", "--test-episodes", "1", "--human-episodes", "1", "--max-steps", "5"]


def _one_line_error(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    return err


def _cache(tmp_path: Path) -> list[str]:
    return ["--cache-dir", str(tmp_path / "cache"), "--no-progress"]


def test_a_checkpoint_of_another_game_is_refused_before_anything_is_filed(tiny_run, tmp_path, capsys):
    frogs = make_run(tmp_path / "other", "lv0", seed=0, game="frogs")
    for flag in ("--checkpoint", "--model"):  # one option, two names
        argv = ["evaluate", str(tiny_run), flag, str(frogs / "model.pt"), *FAST, *_cache(tmp_path)]
        err = _one_line_error(argv, capsys)
        assert "is a frogs model" in err and f"the run {tiny_run.resolve()} needs a zelda model" in err
        assert not (tiny_run / "eval").exists()


def test_a_model_of_another_observation_kind_is_refused(tiny_run, tmp_path, capsys):
    saved = torch.load(tiny_run / "model.pt", weights_only=True)
    pixels = tmp_path / "pixels.pt"
    save_model(pixels, saved["model"], {**saved["config"], "env": {"obs": "pixels"}}, 1000)
    err = _one_line_error(["evaluate", str(tiny_run), "--checkpoint", str(pixels), *FAST], capsys)
    assert "(pixels, compact hidden=16), but the run" in err and "differ in obs" in err


def test_weights_that_do_not_fit_the_network_are_one_line(tiny_run, tmp_path, capsys):
    saved = torch.load(tiny_run / "model.pt", weights_only=True)
    wider = make_run(tmp_path / "wide", "lv0", seed=0)
    other = torch.load(wider / "model.pt", weights_only=True)
    other["model"] = {k: torch.cat([v, v]) if v.dim() else v for k, v in saved["model"].items()}
    torch.save(other, tmp_path / "wrong-shapes.pt")  # format 1: no identity, its config says hidden=16
    argv = ["evaluate", str(tiny_run), "--checkpoint", str(tmp_path / "wrong-shapes.pt"), "--levels"]
    err = _one_line_error([*argv, "zelda_lvl0", "--episodes", "1", "--no-progress"], capsys)
    assert "its weights do not fit the run's network (size mismatch for " in err
    assert "in the file, " in err and "in the network (and " in err and "torch.Size" not in err


def test_a_crafted_checkpoint_is_refused_and_runs_nothing(tiny_run, tmp_path, capsys):
    marker = tmp_path / "written-by-the-checkpoint"

    class Payload:
        def __reduce__(self):
            return (Path.write_text, (marker, "ran"))

    crafted = tmp_path / "crafted.pt"
    torch.save({"model": Payload(), "config": {}, "frames": 1}, crafted)
    err = _one_line_error(["evaluate", str(tiny_run), "--checkpoint", str(crafted), *FAST], capsys)
    assert "refused to load" in err and "could run code" in err
    assert not marker.exists()


def test_a_small_file_of_a_huge_view_is_refused_without_materialising_it(tiny_run, tmp_path, capsys):
    saved = torch.load(tiny_run / "model.pt", weights_only=True)
    name = next(iter(saved["model"]))
    # 4 stored bytes shown as 4M values (a crafted file shows billions: 160 GB to check them)
    saved["model"][name] = torch.zeros(1).as_strided((2000, 2000), (0, 0))
    torch.save(saved, tmp_path / "view.pt")
    assert (tmp_path / "view.pt").stat().st_size < 100_000
    err = _one_line_error(
        ["evaluate", str(tiny_run), "--checkpoint", str(tmp_path / "view.pt"), *FAST], capsys
    )
    assert str(tmp_path / "view.pt") in err and f"tensor model.{name} shows 4000000 values" in err
    assert "stores 1;" in err and "crafted" in err


def _diverge(run_dir: Path) -> None:
    saved = torch.load(run_dir / "model.pt", weights_only=True)
    name = next(iter(saved["model"]))
    saved["model"][name] = torch.full_like(saved["model"][name], math.nan)
    torch.save(saved, run_dir / "model.pt")


def test_evaluate_refuses_a_diverged_model(tiny_run, tmp_path, capsys):
    _diverge(tiny_run)
    err = _one_line_error(["evaluate", str(tiny_run), *FAST, *_cache(tmp_path)], capsys)
    assert "weights are not finite" in err and "diverged" in err


def test_report_leaves_out_a_diverged_run(tmp_path, caplog):
    root = tmp_path / "multirun"
    good, bad = make_run(root, "lv0", seed=0), make_run(root, "lv0", seed=1)
    scores = dict.fromkeys(("pcg0.5", "pcg1", "lv0", "lv1", "lv2", "lv3", "lv4"), [1.0, 1.0])
    model = str((good / "model.pt").resolve())
    write_records(run_results_path(good, PROTOCOL), fake_records(str(good), scores, 1000, model))
    write_records(random_results_path("zelda", PROTOCOL, tmp_path / "cache"), fake_records("random", scores))
    _diverge(bad)
    with caplog.at_level(logging.WARNING):
        report = build_report([root], tmp_path / "out", PROTOCOL, tmp_path / "cache", evaluate=False)
    trained = [row for row in report.tables[0].rows if row.kind == "trained"]
    assert [row.runs for row in trained] == [[str(good.resolve())]]
    assert f"{bad.resolve()} left out of the report" in caplog.text


def _hold(folder: Path, name: str = ".lock") -> int:
    """This process takes ``folder``'s lock the way another gvgai-pcg process would (a new open
    file description conflicts like another process's); returns the descriptor."""
    folder.mkdir(parents=True, exist_ok=True)
    fd = os.open(folder / name, os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_EX)
    os.pwrite(fd, b"pid=4242\nhost=elsewhere\nsince=today\n", 0)
    return fd


def test_two_evaluations_of_one_run_do_not_write_at_once(tiny_run, tmp_path, capsys):
    fd = _hold(tiny_run / "eval")
    try:
        err = _one_line_error(["evaluate", str(tiny_run), *FAST, *_cache(tmp_path)], capsys)
    finally:
        os.close(fd)
    assert "is in use by PID 4242 on host elsewhere since today" in err
    assert not run_results_path(tiny_run, Protocol(1, 1, 1, 5)).exists()


def test_two_reports_into_one_folder_do_not_write_at_once(tiny_run, tmp_path, capsys):
    fd = _hold(tmp_path / "out")
    try:
        argv = ["report", str(tiny_run), "--out", str(tmp_path / "out"), "--no-evaluate", *_cache(tmp_path)]
        err = _one_line_error(argv, capsys)
    finally:
        os.close(fd)
    assert f"{tmp_path / 'out'} is in use by PID 4242" in err and "the report" in err


def test_the_random_agents_cache_has_one_writer(tmp_path, capsys):
    path = random_results_path("zelda", Protocol(1, 1, 1, 5), tmp_path / "cache")
    fd = _hold(path.parent, f".{path.name}.lock")
    try:
        argv = ["evaluate", "--agent", "random", "--game", "zelda", "--protocol", *FAST, *_cache(tmp_path)]
        err = _one_line_error(argv, capsys)
    finally:
        os.close(fd)
    assert "PID 4242" in err and "random agent's cache" in err


@pytest.mark.parametrize("game", ["zelda", "solarfox", "frogs", "boulderdash"])
@pytest.mark.parametrize("obs", ["tiles", "pixels"])
def test_policy_observation_shape_is_the_envs(game, obs):
    """The loader sizes the network without building an env; it must agree with the env's spec."""
    from gvgai_pcg.envs import GVGAIEnv
    from gvgai_pcg.evaluation.policy import observation_shape
    from gvgai_pcg.levels import human_level

    env = GVGAIEnv(game, 1, human_level(game, 4), obs=obs)
    assert observation_shape(game, obs) == tuple(env.observation_spec[obs].shape[-3:])
