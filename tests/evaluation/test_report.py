"""The report from small fake run directories, checked cell by cell."""

import csv
import math

import pytest
import torch

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.evaluator import LevelRecord, random_results_path, run_results_path, write_records
from gvgai_pcg.evaluation.max_score import mean_max_score
from gvgai_pcg.evaluation.protocol import Protocol, protocol_test_sets
from gvgai_pcg.report import build_report
from gvgai_pcg.report.render import markdown_table
from gvgai_pcg.report.table import format_frames
from tests.evaluation.conftest import make_run, write_log

PROTOCOL = Protocol(test_levels=2, test_episodes=1, human_episodes=2, max_steps=10)
HUMAN = ("lv1", "lv2", "lv3", "lv4")


def fake_records(agent: str, scores: dict[str, list[float]], frames: int = 0, checkpoint: str = "") -> list:
    """Records of ``agent``: the scores of each test set's episodes, level after level."""
    records = []
    for s in protocol_test_sets("zelda", PROTOCOL):
        values = scores[s.name]
        for i, level in enumerate(s.levels):
            part = values[i * s.episodes : (i + 1) * s.episodes]
            records.append(
                LevelRecord(agent, "zelda", s.name, level.name, level.seed, s.episodes, part,
                            [10] * len(part), [False] * len(part), 0, PROTOCOL.as_dict(), frames, checkpoint)
            )  # fmt: skip
    return records


@pytest.fixture
def multirun(tmp_path):
    root = tmp_path / "multirun"
    runs = {
        ("lv0", 0): {"pcg0.5": [1, 3], "pcg1": [0, 0], "lv0": [4, 6], **dict.fromkeys(HUMAN, [1, 1])},
        ("lv0", 1): {"pcg0.5": [0, 2], "pcg1": [1, 1], "lv0": [8, 8], **dict.fromkeys(HUMAN, [3, 3])},
        ("ppcg", 0): {"pcg0.5": [2, 2], "pcg1": [1, 1], "lv0": [7, 7], **dict.fromkeys(HUMAN, [0, 0])},
    }
    for (regimen, seed), scores in runs.items():
        frames = 1000 if regimen == "lv0" else 2000
        run_dir = make_run(root, regimen, seed, frames=frames)
        model = str((run_dir / "model.pt").resolve())
        write_records(run_results_path(run_dir, PROTOCOL), fake_records(str(run_dir), scores, frames, model))
        write_log(run_dir, [(f, seed + f / 1000, 0.1 * f / 1000 if regimen == "ppcg" else math.nan) for f in
                            range(100, frames + 1, 100)])  # fmt: skip
    random = fake_records("random", {s: [-1.0] * 2 for s in ("pcg0.5", "pcg1", "lv0", *HUMAN)})
    write_records(random_results_path("zelda", PROTOCOL, tmp_path / "cache"), random)
    return root


def test_table_cell_by_cell(multirun, tmp_path):
    report = build_report([multirun], tmp_path / "out", PROTOCOL, tmp_path / "cache", evaluate=False)
    (table,) = report.tables
    sets = protocol_test_sets("zelda", PROTOCOL)
    pcg_max = [f"{mean_max_score(s.levels):.2f}" for s in sets[:2]]
    assert markdown_table(table).splitlines() == [
        "|  | PCG 0.5 | PCG 1 | Lv 0 | Lv 1 | Lv 2 | Lv 3 | Lv 4 |",
        "|---|---|---|---|---|---|---|---|",
        f"| Max | {pcg_max[0]} | {pcg_max[1]} | 8.00 | 8.00 | 8.00 | 10.00 | 8.00 |",
        "| Random | -1.00 | -1.00 | -1.00 | -1.00 | -1.00 | -1.00 | -1.00 |",
        "| Lv 0 (1k) | 1.50 ± 0.50 | 0.50 ± 0.50 | 6.50 ± 1.50 † | **2.00 ± 1.00** | **2.00 ± 1.00** "
        "| **2.00 ± 1.00** | **2.00 ± 1.00** |",
        "| PPCG (2k) | **2.00** | **1.00** | **7.00** | 0.00 | 0.00 | 0.00 | 0.00 |",  # one run: no ± 0.00
    ]
    with open(report.csv) as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 4 * 7
    lv0 = next(r for r in rows if r["row"] == "Lv 0 (1k)" and r["test_set"] == "lv0")
    assert (lv0["mean"], lv0["std"], lv0["runs"], lv0["training"], lv0["best"]) == (
        "6.5",
        "1.5",
        "2",
        "1",
        "0",
    )
    assert lv0["seed_means"] == "5;8"  # each run's mean; the 95 % t interval with 1 degree of freedom:
    assert float(lv0["ci95_low"]) == pytest.approx(6.5 - 12.706 * 1.5, abs=1e-3)
    assert float(lv0["ci95_high"]) == pytest.approx(6.5 + 12.706 * 1.5, abs=1e-3)
    ppcg = next(r for r in rows if r["row"] == "PPCG (2k)" and r["test_set"] == "lv0")
    assert (ppcg["std"], ppcg["ci95_low"], ppcg["seed_means"]) == ("", "", "7")
    html = report.html.read_text()
    assert '<td class="train">6.50 ± 1.50 †</td>' in html and "<strong>7.00</strong>" in html
    assert "| Lv 0 (1k) |" in report.markdown.read_text()


def test_curves_are_written_per_game(multirun, tmp_path):
    report = build_report([multirun], tmp_path / "out", PROTOCOL, tmp_path / "cache", evaluate=False)
    paths = report.figures["zelda"]
    assert [p.name for p in paths] == ["curves-zelda.png", "curves-zelda.svg"]
    assert all(p.stat().st_size > 1000 for p in paths)


def test_pooled_curve_is_the_mean_and_std_across_runs(multirun):
    from gvgai_pcg.report.curves import pool_runs

    curve = pool_runs("Lv 0", sorted(multirun.glob("zelda-lv0-*")), window=1)
    # seed 0 logs frames/1000, seed 1 one more: mean +0.5, std 0.5 at every frame
    assert curve.runs == 2 and curve.frames[0] == 100 and curve.frames[-1] == 1000
    assert curve.mean == pytest.approx(curve.frames / 1000 + 0.5)
    assert curve.std == pytest.approx(0.5)


def test_report_command(multirun, tmp_path, capsys):
    args = ["--test-levels", "2", "--test-episodes", "1", "--human-episodes", "2", "--max-steps", "10"]
    cache = ["--cache-dir", str(tmp_path / "cache")]
    assert main(["report", str(multirun), *args, *cache, "--no-evaluate"]) == 0
    assert (multirun / "report" / "results.md").is_file() and (multirun / "report" / "results.html").is_file()
    assert "PPCG (2k)" in capsys.readouterr().out


def _rows(report) -> dict[str, int]:
    """Trained row name -> number of runs behind it (from the CSV's Lv 0 column)."""
    with open(report.csv) as handle:
        rows = [r for r in csv.DictReader(handle) if r["test_set"] == "lv0"]
    return {r["row"]: int(r["runs"]) for r in rows if r["row"] not in ("Max", "Random")}


def _curve_labels(monkeypatch) -> list[str]:
    labels: list[str] = []
    monkeypatch.setattr(
        "gvgai_pcg.report.build.plot_curves",
        lambda game, curves, out, reached=None: labels.extend(c.label for c in curves) or [],
    )
    return labels


def test_curves_follow_the_rows_of_the_table(multirun, tmp_path, monkeypatch):
    """A condition is a regimen and a frame count, in the curves as in the table."""
    longer = make_run(multirun, "lv0", seed=2, frames=2000)
    scores = {"pcg0.5": [0, 0], "pcg1": [0, 0], "lv0": [5, 5], **dict.fromkeys(HUMAN, [0, 0])}
    model = str((longer / "model.pt").resolve())
    write_records(run_results_path(longer, PROTOCOL), fake_records(str(longer), scores, 2000, model))
    write_log(longer, [(f, 1.0, math.nan) for f in range(100, 2001, 100)])
    labels = _curve_labels(monkeypatch)
    report = build_report([multirun], tmp_path / "out", PROTOCOL, tmp_path / "cache", evaluate=False)
    assert _rows(report) == {"Lv 0 (1k)": 2, "Lv 0 (2k)": 1, "PPCG (2k)": 1}
    assert sorted(labels) == ["Lv 0 (1k)", "Lv 0 (2k)", "PPCG (2k)"]


def test_results_of_an_older_model_are_left_out_without_evaluating(multirun, tmp_path, monkeypatch):
    retrained = multirun / "zelda-lv0-seed1"
    saved = torch.load(retrained / "model.pt", weights_only=False)
    torch.save({**saved, "frames": 1500}, retrained / "model.pt")  # trained on; results are of 1k
    labels = _curve_labels(monkeypatch)
    report = build_report([multirun], tmp_path / "out", PROTOCOL, tmp_path / "cache", evaluate=False)
    assert _rows(report) == {"Lv 0 (1k)": 1, "PPCG (2k)": 1}
    assert sorted(labels) == ["Lv 0 (1k)", "PPCG (2k)"]


def test_a_run_named_twice_counts_once(multirun, tmp_path, monkeypatch):
    run = multirun / "zelda-ppcg-seed0"
    monkeypatch.chdir(multirun)
    paths = [run, run.relative_to(multirun), multirun]
    report = build_report(paths, tmp_path / "out", PROTOCOL, tmp_path / "cache", evaluate=False)
    assert _rows(report) == {"Lv 0 (1k)": 2, "PPCG (2k)": 1}


@pytest.mark.parametrize(
    ("frames", "text"), [(640, "640"), (1000, "1k"), (79_360, "79.4k"), (999_600, "1M"), (40_000_000, "40M")]
)
def test_frame_counts_are_written_short(frames, text):
    assert format_frames(frames) == text


def test_ppcg_curve_shows_the_studys_highest_difficulty(monkeypatch, tmp_path):
    import numpy as np

    from gvgai_pcg.report import curves

    figures = []
    monkeypatch.setattr(curves, "save_figure", lambda fig, out: figures.append(fig) or [])
    grid = np.linspace(0, 1e6, 5)
    ppcg = curves.PooledCurve("PPCG (1M)", 2, grid, grid * 0, grid * 0, np.linspace(0, 0.3, 5))
    pcg = curves.PooledCurve("PCG 1 (1M)", 2, grid, grid * 0, grid * 0, np.full(5, 1.0))
    from gvgai_pcg.study.verdicts.table1 import STUDY_REACHED

    curves.plot_curves("boulderdash", [ppcg, pcg], tmp_path / "c", STUDY_REACHED)
    twins = [ax for ax in figures[0].axes if ax.get_ylabel() == "difficulty"]

    def dashed(ax) -> list[float]:
        return [line.get_ydata()[0] for line in ax.get_lines() if line.get_linestyle() == "--"]

    assert dashed(twins[0]) == [0.2] and dashed(twins[1]) == []  # only PPCG, at the study's d
    figures.clear()
    curves.plot_curves("boulderdash", [ppcg], tmp_path / "c")  # no published account given: no line
    assert [dashed(ax) for ax in figures[0].axes if ax.get_ylabel() == "difficulty"] == [[]]
