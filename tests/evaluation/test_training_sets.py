"""Runs that trained on a set of levels of their own: the evaluation plays that set as the run's
``train`` test set, the report marks it, and a sweep over ``num_levels`` gets its figure."""

from __future__ import annotations

import csv

import pytest

from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.evaluator import evaluate_run
from gvgai_pcg.evaluation.protocol import Protocol, training_test_set
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels import human_level
from gvgai_pcg.report import build_report
from gvgai_pcg.report.render import markdown_table
from tests.evaluation.conftest import make_run

PROTOCOL = Protocol(test_levels=2, test_episodes=1, human_episodes=1, max_steps=10)


def pcg(num_levels: int, difficulty: float = 1.0) -> dict:
    tag = f"pcg{difficulty}" + (f"-n{num_levels}" if num_levels else "")
    return {"name": "pcg", "difficulty": difficulty, "num_levels": num_levels, "start_seed": 0,
            "win_rule": "game", "tag": tag}  # fmt: skip


@pytest.mark.parametrize(("count", "levels", "episodes"), [(1, 1, 2), (2, 2, 1), (100, 2, 1)])
def test_the_train_set_has_as_many_episodes_as_a_test_set(count, levels, episodes):
    own = training_test_set([generate_level("zelda", 1.0, s) for s in range(count)], PROTOCOL)
    assert (own.name, len(own.levels), own.episodes) == ("train", levels, episodes)


def test_a_finite_generated_run_is_evaluated_on_its_own_levels(tmp_path):
    info = run_info(make_run(tmp_path, "pcg", 0, regimen_config=pcg(3)))
    assert (info.label, info.training_sets) == ("PCG 1, 3 levels", ("train",))
    records = evaluate_run(info, PROTOCOL, progress=False)
    own = [r for r in records if r.test_set == "train"]
    assert [(r.level_seed, r.episodes) for r in own] == [(0, 1), (1, 1)]
    assert {r.test_set for r in records} == {"train", "pcg0.5", "pcg1", "lv0", "lv1", "lv2", "lv3", "lv4"}
    unlimited = run_info(make_run(tmp_path, "pcg-unlimited", 0, regimen_config=pcg(0)))
    assert (unlimited.label, unlimited.training_sets, unlimited.has_training_set) == ("PCG 1", (), False)


def test_a_level_set_marks_the_test_sets_it_shares_levels_with(tmp_path):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "copy_of_lvl2.txt").write_text(str(human_level("zelda", 2)))
    (folder / "own.txt").write_text("wwwwww\nwA.+gw\nwwwwww\n")
    regimen = {"name": "levels", "path": str(folder), "tag": "levels-mine"}
    info = run_info(make_run(tmp_path / "runs", "levels", 0, regimen_config=regimen))
    assert (info.label, info.training_sets) == ("Levels mine", ("train", "lv2"))
    assert [lv.name for lv in info.training_levels()] == ["copy_of_lvl2", "own"]


def test_the_report_has_a_train_column_and_the_level_count_figure(tmp_path):
    root = tmp_path / "sweep"
    for count in (0, 1, 2):
        for seed in (0, 1):
            make_run(root, f"pcg-n{count}", seed, regimen_config=pcg(count))
    make_run(root, "lv0", 0)
    report = build_report([root], tmp_path / "out", PROTOCOL, tmp_path / "cache", progress=False)
    (table,) = report.tables
    assert table.columns[-1] == "train"
    lines = markdown_table(table).splitlines()
    assert lines[0].endswith("| Lv 4 | Train |")
    names = [line.split(" | ")[0].removeprefix("| ") for line in lines[2:]]
    assert names == [
        "Max",
        "Random",
        "Lv 0 (1k)",
        "PCG 1 (1k)",
        "PCG 1, 1 level (1k)",
        "PCG 1, 2 levels (1k)",
    ]
    rows = {row.name: row for row in table.rows}
    assert "train" not in rows["Max"].cells and "train" not in rows["PCG 1 (1k)"].cells
    own = rows["PCG 1, 2 levels (1k)"].cells["train"]
    assert own.training and not own.best and own.runs == 2
    assert lines[-1].endswith(" † |")
    with open(report.csv) as handle:
        train = [r for r in csv.DictReader(handle) if r["test_set"] == "train"]
    assert {r["row"] for r in train} == {"PCG 1, 1 level (1k)", "PCG 1, 2 levels (1k)"}
    assert {r["training"] for r in train} == {"1"}
    figures = [p.name for p in report.figures["zelda"]]
    assert figures[-2:] == ["generalisation-zelda.png", "generalisation-zelda.svg"]
    assert "![zelda: score against the number of training levels](generalisation-zelda.png)" in (
        report.markdown.read_text()
    )


def test_one_set_size_draws_no_level_count_figure(tmp_path):
    root = tmp_path / "runs"
    make_run(root, "pcg-n2", 0, regimen_config=pcg(2))
    make_run(root, "pcg", 0, regimen_config=pcg(0))
    report = build_report([root], tmp_path / "out", PROTOCOL, tmp_path / "cache", progress=False)
    assert not any("generalisation" in p.name for p in report.figures.get("zelda", []))


def test_a_level_of_the_large_test_set_marks_that_set_too(tmp_path):
    from gvgai_pcg.levels.large_test_sets import frozen_large_test_set
    from gvgai_pcg.levels.test_sets import frozen_test_set

    level = frozen_large_test_set("zelda", 1.0)[-1]
    assert level not in set(frozen_test_set("zelda", 1.0))  # only the 100-level family holds it
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "large_last.txt").write_text(str(level))
    regimen = {"name": "levels", "path": str(folder), "tag": "levels-mine"}
    info = run_info(make_run(tmp_path / "runs", "levels", 0, regimen_config=regimen))
    assert info.training_sets == ("train", "pcg1")
