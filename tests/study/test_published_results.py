"""The results committed under ``results/`` rebuild the committed tables: the page's promise."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

RESULTS = Path(__file__).resolve().parents[2] / "results"
# a published study (reproduce --publish: runs and their report); results/pilot has runs only
PUBLISHED = (
    sorted(path for path in RESULTS.glob("*") if (path / "runs").is_dir() and (path / "report").is_dir())
    if RESULTS.is_dir()
    else []
)


def protocol_options(budget: str) -> list[str]:
    """``report``'s options for the protocol of the budget a published folder is named after."""
    from gvgai_pcg.study import BUDGETS

    settings = BUDGETS[budget].protocol if budget in BUDGETS else {}
    return [f"--{key.replace('_', '-')}={value}" for key, value in settings.items()]


@pytest.mark.parametrize("published", PUBLISHED, ids=lambda path: path.name)
def test_the_published_runs_rebuild_the_published_table(published, tmp_path):
    command = [sys.executable, "-m", "gvgai_pcg.cli", "report", "--no-evaluate", str(published / "runs")]
    command += ["--cache-dir", str(published / "random"), "--out", str(tmp_path), "--no-progress"]
    command += protocol_options(published.name)
    subprocess.run(command, check=True, capture_output=True, timeout=600)
    rebuilt = list(csv.reader(open(tmp_path / "results.csv")))
    assert rebuilt == list(csv.reader(open(published / "report" / "results.csv")))
    assert any(row[2] == "trained" for row in rebuilt[1:]), "no trained run in the table"


def test_results_hold_the_small_budget():
    assert "small" in [path.name for path in PUBLISHED]
