"""``gvgai-pcg report --ued``: the UED table of a user's runs, with the curricula page's intervals
over seeds, Welch comparisons against a baseline and Holm's correction (its own verdict code)."""

from __future__ import annotations

import json

import pytest

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.evaluator import random_results_path, run_results_path, write_records
from gvgai_pcg.evaluation.ued import UEDProtocol
from gvgai_pcg.study.verdicts.comparison import CurriculumRuns, comparison_markdown
from tests.evaluation.conftest import make_run
from tests.evaluation.test_report import HUMAN, PROTOCOL, fake_records

UED = UEDProtocol(levels=4, seeds=2, max_steps=10)
STUDY = ["--test-levels", "2", "--test-episodes", "1", "--human-episodes", "2", "--max-steps", "10"]
UED_ARGS = ["--ued", "--ued-levels", "4", "--ued-seeds", "2"]
# per run: its human-level score and its UED score CVaR at 10 % (Lv 0 far behind PPCG on the tail)
RUNS = {
    ("lv0", 0): (1.0, 0.0),
    ("lv0", 1): (1.1, 0.1),
    ("lv0", 2): (0.9, -0.1),
    ("ppcg", 0): (1.0, 2.0),
    ("ppcg", 1): (1.2, 2.1),
    ("ppcg", 2): (0.8, 1.9),
}


def ued_summary(cvar10: float) -> dict:
    """A UED summary whose score CVaR at 10 % is ``cvar10`` (and at 1 %, 0)."""
    cvar = {"metric": "score", "levels": 1, "naive": 0.0, "interval": [0.0, 0.0]}
    return {
        "levels": 4,
        "episodes": 8,
        "solved_rate": 0.25,
        "solved_interval": [0.0, 0.7],
        "mean_score": cvar10 + 1,
        "score_interval": [0.0, 3.0],
        "cvars": [{**cvar, "alpha": 0.01, "corrected": 0.0}, {**cvar, "alpha": 0.1, "corrected": cvar10}],
    }


@pytest.fixture
def runs(tmp_path):
    """Six runs with the study protocol's records and a UED record each, and the random agent's."""
    root = tmp_path / "runs"
    for (regimen, seed), (human, cvar10) in RUNS.items():
        run = make_run(root, regimen, seed)
        model = str((run / "model.pt").resolve())
        scores = {"pcg0.5": [0, 0], "pcg1": [0, 0], "lv0": [human] * 2, **dict.fromkeys(HUMAN, [human] * 2)}
        write_records(run_results_path(run, PROTOCOL), fake_records(str(run), scores, 1000, model))
        record = {"agent": str(run), "game": "zelda", "protocol": UED.as_dict(), "frames": 1000}
        (run / "eval" / f"ued-{UED.key}.json").write_text(
            json.dumps({**record, "summary": ued_summary(cvar10)})
        )
    random = fake_records("random", {s: [-1.0] * 2 for s in ("pcg0.5", "pcg1", "lv0", *HUMAN)})
    write_records(random_results_path("zelda", PROTOCOL, tmp_path / "cache"), random)
    return root


def test_the_report_s_ued_table_is_the_curricula_page_s_on_the_runs(runs, tmp_path, capsys):
    cache = ["--cache-dir", str(tmp_path / "cache")]
    assert main(["report", str(runs), *STUDY, *cache, *UED_ARGS, "--no-evaluate", "--no-progress"]) == 0
    table = (runs / "report" / "ued.md").read_text()
    assert "UED solved rate" in table and "UED score CVaR 10 %" in table
    assert "| Lv 0 | 3 | 1,000 |" in table and "0.00 [-0.25, 0.25]" in table  # 95 % t over three seeds
    assert "Holm's correction over all 3 comparisons" in table
    assert "Lv 0 beats PPCG: **does not hold** (difference -2.00" in table  # the tail, decided
    expected = {
        "Lv 0": CurriculumRuns("Lv 0", "lv", [1000] * 3),
        "PPCG": CurriculumRuns("PPCG", "ppcg", [1000] * 3),
    }
    for (regimen, _), (human, cvar10) in RUNS.items():
        runs_of = expected["Lv 0" if regimen == "lv0" else "PPCG"]
        for metric, value in (("human", human), ("cvar1", 0.0), ("cvar10", cvar10)):
            runs_of.add(metric, value)
    verdicts = comparison_markdown({"zelda": expected}).split("#### Does any curriculum beat PPCG?")[1]
    assert verdicts in table  # the page's verdicts, computed by the page's code
    assert "UED table: " in capsys.readouterr().out


def test_another_baseline_and_a_missing_one(runs, tmp_path):
    cache = ["--cache-dir", str(tmp_path / "cache")]
    common = ["report", str(runs), *STUDY, *cache, *UED_ARGS, "--no-evaluate", "--no-progress"]
    assert main([*common, "--baseline", "Lv 0"]) == 0
    assert "PPCG beats Lv 0: **holds**" in (runs / "report" / "ued.md").read_text()
    assert main([*common, "--baseline", "DR"]) == 0
    assert (
        "No DR run here to compare with; --baseline takes one of: Lv 0, PPCG."
        in (runs / "report" / "ued.md").read_text()
    )


def test_the_report_evaluates_the_ued_protocol_where_a_run_lacks_it(tmp_path, capsys):
    run = make_run(tmp_path / "runs", "ppcg", 0)
    cache = ["--cache-dir", str(tmp_path / "cache")]
    study = ["--test-levels", "1", "--test-episodes", "1", "--human-episodes", "1", "--max-steps", "10"]
    tail = ["--ued-rank-episodes", "2", "--ued-score-episodes", "2"]  # the tail protocol, kept small
    assert (
        main(["report", str(run), *study, *cache, "--ued", "--ued-levels", "2", *tail, "--no-progress"]) == 0
    )
    assert list((run / "eval").glob("ued-*.csv"))  # played, and kept for the next report
    table = (tmp_path / "runs" / "report" / "ued.md").read_text()
    assert "| PPCG | 1 | 1,000 |" in table and "UED win-rate CVaR 1 %" in table
    assert table.startswith("# UED protocol: 2 generated levels x (2 episodes to rank + 2 to score)")
