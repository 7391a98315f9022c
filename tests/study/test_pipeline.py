"""The study pipeline: its conditions, how a sweep is shared and ordered, and publish -> rebuild."""

from __future__ import annotations

import csv
import os
import signal
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import pytest
from hydra import compose, initialize_config_dir

from gvgai_pcg.config import config_dir
from gvgai_pcg.evaluation.checkpoints import find_runs, run_info
from gvgai_pcg.evaluation.protocol import Protocol
from gvgai_pcg.rundir.provenance import code_commit, session_commits
from gvgai_pcg.study import BUDGETS, STUDY_CONDITIONS
from gvgai_pcg.study.pages.page import write_results_page
from gvgai_pcg.study.pipeline import (
    planned_configs,
    published_elsewhere,
    reproduce,
    run_sweep,
    share_conditions,
    sweep_arguments,
    sweep_plan,
)
from gvgai_pcg.study.sweeps.conditions import EXTRA_CONDITIONS, conditions_of, known_conditions
from tests.waiting import PATIENCE_S

PROTOCOL = Protocol(**BUDGETS["smoke"].protocol)
REGIMEN_NAMES = {"lv0": "lv", "lv4": "lv", "lv0-3": "lv0-3", "pcg0.5": "pcg", "pcg1": "pcg", "ppcg": "ppcg"}


@pytest.mark.parametrize("condition", known_conditions())
def test_every_condition_is_a_config_of_its_game_and_regimen(condition):
    game, tag = condition.split("-", 1)
    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        cfg = compose("config", overrides=[f"condition={condition}"])
    assert cfg.game.name == game and cfg.regimen.name == REGIMEN_NAMES[tag]
    assert cfg.regimen.tag.removesuffix(".0") == tag  # pcg1 is tagged pcg1.0 in run names
    assert cfg.run_name.startswith(f"{game}-")


def test_the_study_conditions_are_table_1_and_the_extras_are_the_rest():
    assert len(STUDY_CONDITIONS) == 12 and sum(c.startswith("zelda") for c in STUDY_CONDITIONS) == 6
    assert len(set(STUDY_CONDITIONS) | set(EXTRA_CONDITIONS)) == 24
    study = [budget for budget in BUDGETS.values() if budget.comparison == "study"]
    assert all(set(budget.conditions) == set(STUDY_CONDITIONS) for budget in study) and len(study) == 4
    assert BUDGETS["small"].frames >= 5_000_000 and len(BUDGETS["small"].seeds) == 3
    assert BUDGETS["paper"].frames == 40_000_000 and "preset=paper" in BUDGETS["paper"].overrides


def test_parallel_jobs_share_the_conditions_by_cost_and_keep_their_order():
    shares = share_conditions(STUDY_CONDITIONS, jobs=2)
    assert sorted(c for share in shares for c in share) == sorted(STUDY_CONDITIONS)
    for share in shares:
        assert share == [c for c in STUDY_CONDITIONS if c in share]
    frogs_and_boulderdash = [sum(c.startswith(("frogs", "boulder")) for c in share) for share in shares]
    assert frogs_and_boulderdash == [2, 2]  # the costly games are not all in one share
    assert share_conditions(["zelda-lv0"], jobs=4) == [["zelda-lv0"]]


def test_a_sweep_varies_the_seed_slowest_and_passes_the_launcher_and_overrides():
    budget = BUDGETS["small"]
    arguments = sweep_arguments(budget, ["zelda-lv0", "frogs-ppcg"], Path("/r"), "ray", ["algo.lr=1e-3"])
    assert arguments[:3] == ["-m", "seed=0,1,2", "condition=zelda-lv0,frogs-ppcg"]
    assert "total_frames=5000000" in arguments and "out_dir=/r" in arguments
    assert arguments[-2:] == ["hydra/launcher=ray", "algo.lr=1e-3"]


def test_a_sweep_skips_finished_pairs_seed_by_seed_and_is_one_multirun_when_none_are():
    budget = BUDGETS["small"]
    conditions = ["zelda-lv0", "frogs-ppcg"]
    assert sweep_plan(budget, conditions) == [((0, 1, 2), conditions)]
    skipped = sweep_plan(budget, conditions, {("zelda-lv0", 0), ("frogs-ppcg", 0), ("zelda-lv0", 1)})
    assert skipped == [((1,), ["frogs-ppcg"]), ((2,), conditions)]
    assert sweep_plan(budget, ["zelda-lv0"], {("zelda-lv0", s) for s in budget.seeds}) == []
    assert sweep_arguments(budget, conditions, Path("/r"), seeds=(2,))[1] == "seed=2"


def test_a_fresh_machine_trains_only_what_the_published_folder_lacks(tmp_path):
    published = tmp_path / "published"
    one_seed, two_seeds = replace(BUDGETS["smoke"], seeds=(0,)), replace(BUDGETS["smoke"], seeds=(0, 1))
    reproduce(one_seed, ["zelda-lv0"], tmp_path / "first", publish_to=published, progress=False)
    # another machine: nothing of the first out folder, only the published one (a clone)
    (published / "report" / "curves-frogs.png").write_bytes(b"a figure of no run any more")
    second = reproduce(two_seeds, ["zelda-lv0"], tmp_path / "second", publish_to=published, progress=False)
    assert not (published / "report" / "curves-frogs.png").exists()
    assert sorted(p.name for p in (tmp_path / "second" / "runs").iterdir() if p.is_dir()) == [
        "zelda-lv0-tiles-compact-seed1"
    ]
    rows = list(csv.DictReader(open(second.report / "results.csv")))
    lv0 = [row for row in rows if row["row"].startswith("Lv 0")]
    assert lv0 and all(row["runs"] == "2" for row in lv0), lv0  # the published seed 0 is in
    assert "Lv 0 2 run(s)" in (second.report / "claims.md").read_text()
    assert sorted(p.name for p in (published / "runs").iterdir()) == [
        "zelda-lv0-tiles-compact-seed0",
        "zelda-lv0-tiles-compact-seed1",
    ]
    # a published run of another config (same name) is trained again, not taken
    other = published_elsewhere(
        two_seeds, ["zelda-lv0"], ["algo.lr=0.001"], tmp_path / "x", published, PROTOCOL
    )
    assert other == (set(), [])
    # an unfinished copy here does not hide, nor overwrite, the finished published run
    cut = tmp_path / "cut"
    run_sweep(one_seed, ["zelda-lv0"], cut, overrides=[f"total_frames={one_seed.frames // 2}"])
    skip, runs = published_elsewhere(two_seeds, ["zelda-lv0"], [], cut, published, PROTOCOL)
    assert skip == {("zelda-lv0", 0), ("zelda-lv0", 1)} and len(runs) == 2
    reproduce(two_seeds, ["zelda-lv0"], cut, train=False, publish_to=published, progress=False)
    assert run_info(published / "runs" / "zelda-lv0-tiles-compact-seed0").frames == one_seed.frames


def test_a_failed_multirun_fails_the_sweep_in_one_line_naming_its_log_and_cause(tmp_path):
    with pytest.raises(ValueError) as failed:
        run_sweep(BUDGETS["smoke"], ["zelda-lv0"], tmp_path, overrides=["algo.no_such_key=1"])
    assert str(failed.value).startswith(
        f"the sweep failed; {tmp_path / 'logs' / 'sweep-0.log'}: gvgai-pcg train: error: algo.no_such_key=1: "
        "unknown key"
    ) and "\n" not in str(failed.value)


def test_reproduce_refuses_a_bad_override_before_the_sweep_starts(tmp_path):
    from gvgai_pcg.config_rules import ConfigError

    with pytest.raises(ConfigError, match=r"^algo\.lr=-1"):
        reproduce(BUDGETS["smoke"], ["zelda-lv0", "zelda-pcg1"], tmp_path / "out", overrides=["algo.lr=-1"])
    assert not (tmp_path / "out").exists()


def test_sigterm_to_the_sweep_stops_its_training_runs_at_a_checkpoint(tmp_path):
    script = (
        "import sys; from pathlib import Path; from gvgai_pcg.study import BUDGETS;"
        "from gvgai_pcg.study.pipeline import run_sweep;"
        "run_sweep(BUDGETS['smoke'], ['zelda-lv0', 'zelda-lv4'], Path(sys.argv[1]), jobs=2,"
        " overrides=['total_frames=10000000', 'checkpoint.every_frames=1000'])"
    )
    quick = {**os.environ, "GVGAI_PCG_COMPILE": "0"}  # a signal's path, not the compiler, is tested here
    sweep = subprocess.Popen(
        [sys.executable, "-c", script, str(tmp_path)], stderr=subprocess.PIPE, text=True, env=quick
    )
    runs = [tmp_path / "runs" / f"zelda-{c}-tiles-compact-seed0" for c in ("lv0", "lv4")]
    checkpoints = [run / "checkpoints" for run in runs]
    try:
        deadline = time.monotonic() + PATIENCE_S
        while not all((c / "last.pt").exists() for c in checkpoints) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert sweep.poll() is None, sweep.stderr.read()
        sweep.send_signal(signal.SIGTERM)
        _, errors = sweep.communicate(timeout=PATIENCE_S)
    finally:
        if sweep.poll() is None:
            sweep.kill()
    assert sweep.returncode != 0 and "KeyboardInterrupt" in errors
    for i in (0, 1):  # each job's training run was told to stop, and did, at a checkpoint
        assert "stopped by SIGTERM" in (tmp_path / "logs" / f"sweep-{i}.log").read_text()


def test_a_report_of_finished_runs_only_evaluates_no_run_still_training(tmp_path):
    budget = BUDGETS["smoke"]
    out = tmp_path / "out"
    run_sweep(budget, ["zelda-lv0"], out, overrides=[f"total_frames={budget.frames // 2}"])  # cut short
    [run] = find_runs([out / "runs"])
    with pytest.raises(FileNotFoundError, match="no run directories"):
        reproduce(budget, ["zelda-lv0"], out, train=False, progress=False, finished_only=True)
    assert not (run / "eval").exists()


def test_a_published_run_rebuilds_the_report_without_its_model(tmp_path):
    out, published = tmp_path / "out", tmp_path / "published"
    budget = BUDGETS["smoke"]
    reproduce(budget, ["zelda-lv0"], out, publish_to=published, progress=False)
    [run] = find_runs([published / "runs"])
    assert (run / "model.pt").is_file()  # whatever its size
    assert run_info(run).frames == budget.frames
    assert_committable(published, Path("results") / budget.name)
    rebuilt = tmp_path / "rebuilt"
    protocol = ["--test-levels", "2", "--human-episodes", "1", "--max-steps", "100"]
    command = [sys.executable, "-m", "gvgai_pcg.cli", "report", "--no-evaluate", str(published / "runs")]
    command += ["--cache-dir", str(published / "random"), "--out", str(rebuilt), "--no-progress", *protocol]
    subprocess.run(command, check=True, capture_output=True)
    original = list(csv.reader(open(out / "report" / "results.csv")))
    assert list(csv.reader(open(rebuilt / "results.csv"))) == original
    assert any(row[1].startswith("Lv 0") for row in original)  # the trained run is in the table
    claims = (out / "report" / "claims.md").read_text()
    assert "| zelda | Trained on one human level (Lv 0, Lv 4)" in claims and "Lv 0 1 run(s)" in claims
    (tmp_path / "images").mkdir()
    (tmp_path / "images" / "curves-frogs.png").write_bytes(b"an earlier report's figure")
    page = tmp_path / "results.md"
    page.write_text("# Results\n\nbefore\n<!-- results:start -->\nold\n<!-- results:end -->\nafter\n")
    write_results_page(page, published, tmp_path / "images", "images/results", budget.frames, "abc1234")
    text = page.read_text()
    assert text.startswith("# Results\n\nbefore\n") and text.endswith("after\n") and "\nold\n" not in text
    assert "| zelda-lv0-tiles-compact-seed0 | 1,600 | yes |" in text and "commit `abc1234`" in text
    trained_at = session_commits(published / "runs" / "zelda-lv0-tiles-compact-seed0")
    assert trained_at == [code_commit()] and f"| `{trained_at[0]}` |" in text
    assert "Training time of these 1 runs: " in text
    assert (
        "](images/results/curves-zelda.png)" in text and (tmp_path / "images" / "curves-zelda.png").is_file()
    )
    assert not (tmp_path / "images" / "curves-frogs.png").exists()


def assert_committable(published: Path, where: Path) -> None:
    """Every file ``publish`` wrote, placed at ``where`` in this checkout (the Makefile's
    ``--publish results/BUDGET``), is one git would commit: an ignore rule there once kept every
    run's data out of the repository while the page said it was in."""
    repo = Path(__file__).resolve().parents[2]
    if not (repo / ".git").exists():
        pytest.skip("not a git checkout")
    files = [str(where / path.relative_to(published)) for path in published.rglob("*") if path.is_file()]
    assert not [name for name in files if name.endswith(".lock")]  # a writer's lock is not data
    assert any("/runs/" in name and name.endswith("log.csv") for name in files)
    found = subprocess.run(
        ["git", "check-ignore", "--no-index", "--stdin"],
        cwd=repo,
        input="\n".join(files),
        capture_output=True,
        text=True,
    )
    assert found.returncode in (0, 1), found.stderr  # 1: nothing ignored; else git failed
    assert found.stdout.split() == [], f"git ignores published files: {found.stdout.split()[:5]}"


@pytest.mark.slow
def test_the_smoke_budget_runs_every_condition_end_to_end(tmp_path):
    command = [sys.executable, "-m", "gvgai_pcg.cli", "reproduce", "--budget", "smoke", "--jobs", "2"]
    command += ["--out", str(tmp_path / "smoke"), "--publish", str(tmp_path / "published"), "--no-progress"]
    subprocess.run(command, check=True, capture_output=True, timeout=1800)
    rows = list(csv.DictReader(open(tmp_path / "smoke" / "report" / "results.csv")))
    games = {row["game"] for row in rows}
    assert games == {"zelda", "solarfox", "frogs", "boulderdash"}
    assert len(find_runs([tmp_path / "published" / "runs"])) == len(STUDY_CONDITIONS)


def test_a_budget_with_per_condition_frames_and_seeds_plans_one_multirun_per_frame_budget():
    budget = replace(
        BUDGETS["small"],
        conditions=("zelda-lv0", "zelda-ppcg"),
        seeds=(0, 1),
        condition_frames={"zelda-ppcg": 20_000_000},
        condition_seeds={"zelda-ppcg": (0, 1, 2)},
    )
    conditions = ["zelda-lv0", "zelda-ppcg"]
    assert budget.runs == 2 + 3 and budget.frames_range == (5_000_000, 20_000_000)
    plan = sweep_plan(budget, conditions)
    assert plan == [
        ((0,), ["zelda-ppcg"]),
        ((0,), ["zelda-lv0"]),
        ((1,), ["zelda-ppcg"]),
        ((1,), ["zelda-lv0"]),
        ((2,), ["zelda-ppcg"]),
    ]
    assert "total_frames=20000000" in sweep_arguments(budget, ["zelda-ppcg"], Path("/r"), seeds=(2,))
    with pytest.raises(ValueError, match="one frame budget"):
        sweep_arguments(budget, conditions, Path("/r"))


def test_the_medium_budget_trains_what_issue_35_asks_and_keeps_models_along_the_way():
    medium = BUDGETS["medium"]
    assert all(medium.frames_of(c) >= 10_000_000 for c in medium.conditions)
    for c in ("zelda-lv0-3", "zelda-pcg0.5", "zelda-pcg1", "zelda-ppcg"):
        assert medium.frames_of(c) >= 20_000_000
    assert all(len(medium.seeds_of(c)) >= 4 for c in medium.conditions)
    assert all(len(medium.seeds_of(c)) >= 5 for c in ("zelda-pcg0.5", "zelda-pcg1", "zelda-ppcg"))
    assert "checkpoint.keep_every_frames=1000000" in medium.overrides
    # the claims judged on at least 100 distinct generated levels per difficulty
    assert medium.protocol == {"test_levels": 100, "test_sets": "large"}


def test_each_results_page_keeps_its_own_figures():
    from gvgai_pcg.study.pages.page import page_images

    assert page_images(Path("docs/results.md")) == (Path("docs/images/results"), "images/results")
    medium, prefix = page_images(Path("docs/results-medium.md"))
    assert medium == Path("docs/images/results-medium") and prefix == "images/results-medium"


def test_publish_refuses_a_folder_holding_a_run_of_another_config(tmp_path):
    import json

    import yaml

    from gvgai_pcg.study.sweeps.publish import publish
    from tests.evaluation.conftest import make_run

    out, dest = tmp_path / "out", tmp_path / "published"
    make_run(out / "runs", "lv0", 0)
    other = make_run(dest / "runs", "lv0", 0)
    config = yaml.safe_load((other / "config.yaml").read_text())
    config["env"]["num_envs"] = 8
    (other / "config.yaml").write_text(yaml.safe_dump(config))
    (other / "published.json").write_text(json.dumps({"checkpoint": "elsewhere/model.pt", "frames": 5000}))
    before = sorted(p.relative_to(dest) for p in dest.rglob("*"))
    with pytest.raises(ValueError) as refused:
        publish(out, dest)
    assert str(refused.value) == (
        f"{other} is a published run of another config (env.num_envs: 8 published, 4 here); publish "
        "into another folder, or move that run away first"
    )
    assert sorted(p.relative_to(dest) for p in dest.rglob("*")) == before  # nothing published


@pytest.mark.parametrize("where", ["out", "out/runs/x"])
def test_publish_refuses_the_sweeps_own_folder_and_writes_nothing_into_its_runs(where, tmp_path):
    from gvgai_pcg.study.sweeps.publish import publish
    from tests.evaluation.conftest import make_run

    out = tmp_path / "out"
    run = make_run(out / "runs", "lv0", 0)
    before = sorted(p.relative_to(out) for p in out.rglob("*"))
    with pytest.raises(
        ValueError, match=rf"^--publish {tmp_path / where}: its runs would be the sweep's own"
    ):
        publish(out, tmp_path / where)
    assert not (run / "published.json").exists()  # else a run that trains on reads as published
    assert sorted(p.relative_to(out) for p in out.rglob("*")) == before


def test_reproduce_refuses_to_publish_into_its_own_out_before_anything_else(tmp_path, capsys):
    from gvgai_pcg.cli import main

    out = tmp_path / "sweep"
    argv = ["reproduce", "--budget", "smoke", "--conditions", "zelda-lv0", "--no-train", "--no-progress"]
    with pytest.raises(SystemExit) as refused:
        main([*argv, "--out", str(out), "--publish", str(out)])
    err = capsys.readouterr().err.strip()
    assert refused.value.code == 2 and len(err.splitlines()) == 1
    assert err.startswith(f"gvgai-pcg reproduce: error: --publish {out}: its runs would be the sweep's own")
    assert not out.exists()


def test_conditions_with_overrides_of_their_own_train_in_a_multirun_of_their_own():
    budget = replace(
        BUDGETS["smoke"],
        name="own",
        conditions=("zelda-pcg1", "zelda-sfl", "zelda-dr"),
        seeds=(0, 1),
        frames=800,
        overrides=("env.num_envs=8",),
        condition_overrides={"zelda-sfl": ("regimen.pool_size=8", "regimen.buffer_size=4")},
    )
    conditions = list(budget.conditions)
    assert sweep_plan(budget, conditions) == [
        ((0,), ["zelda-pcg1", "zelda-dr"]),
        ((0,), ["zelda-sfl"]),
        ((1,), ["zelda-pcg1", "zelda-dr"]),
        ((1,), ["zelda-sfl"]),
    ]
    arguments = sweep_arguments(budget, ["zelda-sfl"], Path("/r"), seeds=(0,))
    assert arguments[-3:] == ["env.num_envs=8", "regimen.pool_size=8", "regimen.buffer_size=4"]
    assert "regimen.pool_size=8" not in sweep_arguments(budget, ["zelda-dr"], Path("/r"))
    with pytest.raises(ValueError, match="one set of overrides"):
        sweep_arguments(budget, conditions, Path("/r"))
    planned = planned_configs(budget, ["zelda-sfl", "zelda-dr"])
    (sfl,) = planned["zelda-sfl", 0].values()
    assert (sfl["regimen"]["pool_size"], sfl["regimen"]["buffer_size"], sfl["env"]["num_envs"]) == (8, 4, 8)


def test_the_curricula_smoke_budget_shrinks_only_sfl_s_pool():
    smoke = BUDGETS["curricula-smoke"]
    assert "regimen.pool_size=8" in smoke.overrides_of("frogs-sfl")
    assert smoke.overrides_of("frogs-plr") == smoke.overrides
    # The comparison runs SFL's reference pool; PLR-robust and ACCEL a buffer fair for 10M frames.
    full = BUDGETS["curricula"]
    assert full.overrides_of("zelda-sfl") == full.overrides
    assert full.overrides_of("frogs-accel")[-1] == "regimen.buffer_size=300"
    assert {c for c in full.condition_overrides} == {
        f"{game}-{name}"
        for game in ("zelda", "solarfox", "frogs", "boulderdash")
        for name in ("plr", "accel", "accel-noselect")
    }
    # ACCEL without selection, the control: the same fair buffer, run only when named
    assert full.overrides_of("zelda-accel-noselect")[-1] == "regimen.buffer_size=300"
    assert "zelda-accel-noselect" in full.controls and "zelda-accel-noselect" not in conditions_of(full, True)
