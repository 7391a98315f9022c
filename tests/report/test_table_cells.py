"""The table's cells: what is bold, and what a cell of one run shows."""

from __future__ import annotations

from gvgai_pcg.report.render import LEGEND, cell_text
from gvgai_pcg.report.table import Cell, Row, mark_best, t_interval


def rows(*means: float) -> list[Row]:
    return [Row(f"R{i}", "trained", {"lv1": Cell(m, 0.0, 3)}) for i, m in enumerate(means)]


def test_tied_zeros_are_not_all_bold_but_a_real_best_is():
    tied = rows(0.0, 0.0, 0.0)
    mark_best(tied, ["lv1"])
    assert not any(r.cells["lv1"].best for r in tied)
    some = rows(0.0, 0.5, 0.5)
    mark_best(some, ["lv1"])
    assert [r.cells["lv1"].best for r in some] == [False, True, True]
    alone = rows(0.0)  # one condition is the best of its column
    mark_best(alone, ["lv1"])
    assert alone[0].cells["lv1"].best


def test_a_single_run_shows_no_spread_and_the_legend_says_what_the_spread_is():
    assert cell_text(Cell(2.0, None, 1)) == "2.00"
    assert cell_text(Cell(2.0, 0.5, 3)) == "2.00 ± 0.50"
    assert "population SD" in LEGEND and "95 % t" in LEGEND
    assert t_interval([1.0]) is None
    low, high = t_interval([1.0, 2.0, 3.0])
    assert (round(low, 3), round(high, 3)) == (-0.484, 4.484)


def config(lr: float, seed: int, **extra) -> dict:
    return {
        "algo": {"lr": lr},
        "seed": seed,
        "out_dir": f"/runs/{seed}",
        "regimen": {"name": "ppcg"},
        **extra,
    }


def test_runs_of_another_learning_rate_are_split_not_averaged_as_seeds():
    from gvgai_pcg.report.table import RunResults, differing_keys, split_by_config

    runs = [
        RunResults("PPCG", 100, (), [], f"r{i}", config(lr, i)) for i, lr in enumerate((7e-4, 7e-4, 1e-3))
    ]
    assert differing_keys([run.config for run in runs]) == ["algo.lr"]
    groups = split_by_config(runs)
    assert {k: [r.path for r in v] for k, v in groups.items()} == {
        "algo.lr=0.0007": ["r0", "r1"],
        "algo.lr=0.001": ["r2"],
    }
    # seeds, output folders and a key added since (at its old value) do not split
    same = [
        RunResults("PPCG", 100, (), [], "a", config(7e-4, 0)),
        RunResults("PPCG", 100, (), [], "b", config(7e-4, 1)),
    ]
    same[1].config["regimen"]["num_levels"] = 0
    assert list(split_by_config(same)) == [""]


def test_the_table_names_each_configs_row_by_its_differing_keys(tmp_path):
    from gvgai_pcg.evaluation.protocol import protocol_test_sets
    from gvgai_pcg.report.table import RunResults, build_table
    from tests.evaluation.test_report import HUMAN, PROTOCOL, fake_records

    scores = {s: [1.0, 1.0] for s in ("pcg0.5", "pcg1", "lv0", *HUMAN)}
    runs = [
        RunResults("PPCG", 1000, (), fake_records(f"r{i}", scores), f"r{i}", config(lr, i))
        for i, lr in enumerate((7e-4, 7e-4, 1e-3))
    ]
    table = build_table("zelda", protocol_test_sets("zelda", PROTOCOL), None, runs)
    rows = {row.name: row.runs for row in table.rows if row.kind == "trained"}
    assert rows == {"PPCG (1k; algo.lr=0.0007)": ["r0", "r1"], "PPCG (1k; algo.lr=0.001)": ["r2"]}
