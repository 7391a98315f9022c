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
