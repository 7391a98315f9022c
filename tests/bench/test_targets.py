"""The speed targets beside a run's figures: met, missed or not measured (no measuring here)."""

from gvgai_pcg.bench import targets as bench_targets
from gvgai_pcg.bench.targets import Check, Section


def test_a_check_is_met_at_its_bound_either_way_and_unmeasured_without_a_figure():
    assert Check("ratio", 3.0, 3.0).met is True
    assert Check("ratio", 3.0, 2.99).met is False
    assert Check("seconds", 30.0, 30.0, unit="s", at_most=True).met is True
    assert Check("seconds", 30.0, 30.5, unit="s", at_most=True).met is False
    assert Check("ratio", 3.0, None).met is None


def test_the_rows_show_the_goal_the_figure_and_the_verdict():
    assert Check("ours / VGDLx", 3.0, 0.934).row() == "| ours / VGDLx | at least 3.00x | 0.93x | missed |"
    row = Check("protocol", 30.0, 12.34, unit="s", at_most=True).row()
    assert row == "| protocol | at most 30.0 s | 12.3 s | met |"
    assert Check("peer", 1.0, None).row() == "| peer | at least 1.00x | - | not measured |"


def test_the_table_counts_what_was_met_and_keeps_the_order():
    checks = [Check("a", 1.0, 2.0), Check("b", 1.0, 0.5), Check("c", 1.0, None)]
    lines = bench_targets.target_lines(checks)
    assert "1 of 3 met." in lines
    assert [line.split(" | ")[0] for line in lines if line.startswith("| ") and "---" not in line] == [
        "| target",
        "| a",
        "| b",
        "| c",
    ]
    assert bench_targets.target_lines([]) == []


def test_sections_add_their_text_and_their_checks_in_order():
    total = Section("one\n", [Check("a", 1.0, 1.0)]) + Section() + Section("two\n", [Check("b", 1.0, 0.0)])
    assert total.text == "one\ntwo\n" and [c.what for c in total.checks] == ["a", "b"]


def test_every_game_at_64_is_set_against_its_baseline_figure():
    checks = bench_targets.env_checks({"zelda": 172_001, "frogs": 39_077, "unknown": 1.0})
    assert [(c.what.split()[0], c.met) for c in checks] == [("zelda", True), ("frogs", False)]
    assert round(checks[1].measured, 2) == 1.0
    assert bench_targets.ratio(1.0, 0.0) is None
