"""The pilot's table: smoothed training scores, and frames and CPU hours to a target."""

from __future__ import annotations

import json

import yaml

from gvgai_pcg.rundir.run_log import COLUMNS
from gvgai_pcg.study.sweeps.pilot import frames_to_reach, main, read_pilot, score_at, smoothed_scores


def _rows(scores: list[float], step: int = 250_000) -> list[dict[str, float]]:
    return [{"frames": (i + 1) * step, "mean_score": s, "time": (i + 1) * 10.0} for i, s in enumerate(scores)]


def test_the_score_is_smoothed_over_a_window_and_a_target_counts_once_the_average_reaches_it():
    rows = _rows([0, 0, 4, 0, 4, 4, 4, 4])  # windows of 2 rows (500k frames)
    assert smoothed_scores(rows)[:3] == [(500_000, 0.0), (750_000, 2.0), (1_000_000, 2.0)]
    assert frames_to_reach(rows, 3.0) == 1_500_000  # the single 4 at 750k is not enough
    assert frames_to_reach(rows, 5.0) is None
    assert score_at(rows, 2_000_000) == 4.0 and score_at(rows, 3_000_000) is None


def test_the_table_reads_a_published_pilot_and_costs_each_run_by_its_cpu_seconds(tmp_path, capsys):
    run = tmp_path / "runs" / "p-e64"
    run.mkdir(parents=True)
    config = {"game": {"name": "zelda"}, "regimen": {"tag": "pcg0.5"}, "env": {"num_envs": 64},
              "algo": {"lr": 0.002}, "seed": 0}  # fmt: skip
    (run / "config.yaml").write_text(yaml.safe_dump(config))
    rows = _rows([1, 1, 3, 3, 3, 3, 3, 3])
    lines = [",".join(COLUMNS)] + [",".join(str(row.get(c, 0)) for c in COLUMNS) for row in rows]
    (run / "log.csv").write_text("\n".join(lines) + "\n")
    (tmp_path / "cpu.json").write_text(json.dumps({"p-e64": 7200.0}))  # 2 CPU hours for 2M frames
    [pilot] = read_pilot(tmp_path)
    assert pilot.cpu_per_frame == 7200.0 / 2_000_000
    main([str(tmp_path)])
    line = capsys.readouterr().out.splitlines()[-1]
    assert "| p-e64 | 64 | 0.002 | 0 | 2.0M | 3600 |" in line
    # the average of the last 500k frames: 2 at 750k, 3 from 1M on
    assert line.endswith("| 3.00 | - | - | 0.75M (0.75) | 1.00M (1.00) | 1.00M (1.00) |")


def test_the_pilot_page_shows_the_table_its_published_runs_give():
    from pathlib import Path

    from gvgai_pcg.study.sweeps.pilot import END, START, page_table

    root = Path(__file__).resolve().parents[2]
    page = (root / "docs" / "pilot.md").read_text()
    block = page.split(START, 1)[1].split(END, 1)[0].strip()
    assert block == page_table(root / "results" / "pilot", root / "results" / "small" / "runs")


def test_the_pilot_pages_protocol_rows_are_the_published_records():
    from pathlib import Path

    from gvgai_pcg.evaluation.evaluator import read_records

    root = Path(__file__).resolve().parents[2]
    page = (root / "docs" / "pilot.md").read_text()
    sets = ("pcg0.5", "pcg1", "lv0", "lv1", "lv2", "lv3", "lv4")
    for run, label in (("p-e64-lr2e-3-s0", "PCG 0.5, lr 2e-3"), ("p-e64-lr2e-3-pcg1-s0", "PCG 1, lr 2e-3")):
        [path] = (root / "results" / "pilot" / "runs" / run / "eval").glob("protocol-*.jsonl")
        scores: dict[str, list[float]] = {}
        for record in read_records(path):
            scores.setdefault(record.test_set, []).extend(record.scores)
        cells = " | ".join(f"{sum(scores[s]) / len(scores[s]):.2f}" for s in sets)
        assert f"| {label} | {cells} |" in page
