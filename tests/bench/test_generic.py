"""The generic VGDL step beside the hand-written engines: its table from fake rates, a tiny eager
measurement of both engines, and "no description yet" for the games without one (the compiled
measurement is slow: torch.compile of both ticks)."""

from __future__ import annotations

import argparse

import pytest

from gvgai_pcg.bench import generic as bench_generic
from gvgai_pcg.bench.generic import GenericRow
from gvgai_pcg.bench.targets import Section
from gvgai_pcg.bench.throughput import Rate
from gvgai_pcg.commands import bench


def _rate(median: float) -> Rate:
    return Rate(median, median / 2, median * 2)


def test_the_table_has_a_row_per_game_and_batch_eager_and_compiled_as_generic_over_hand_written():
    rows = [
        GenericRow("zelda", 12, "eager", _rate(10_000), _rate(7_000)),
        GenericRow("zelda", 12, "compiled", _rate(20_000), _rate(21_000)),
        GenericRow("zelda", 4096, "eager", _rate(500_000), _rate(400_000)),
    ]
    lines = bench_generic.generic_lines(rows, ["frogs", "solarfox"], "load average 1.0")
    header = next(line for line in lines if line.startswith("| game |"))
    table = [line for line in lines if line.startswith("| zelda")]
    assert [line.count("|") for line in table] == [header.count("|")] * 2
    assert table[0] == (
        "| zelda | 12 | 10,000 (5,000) | 7,000 (3,500) | 0.70x | 20,000 (10,000) | 21,000 (10,500) | 1.05x |"
    )
    assert table[1].endswith("| 0.80x | - | - | - |")  # not measured compiled
    assert lines[-1] == "No description yet: frogs, solarfox."
    assert "load average 1.0" in " ".join(lines)


@pytest.fixture
def without_solarfox(monkeypatch):
    """Every study game is described: leave one out to see an undescribed one reported."""
    described = {name: entry for name, entry in bench_generic.vgdl_games().items() if name != "solarfox"}
    monkeypatch.setattr(bench_generic, "vgdl_games", lambda: described)


def test_only_the_described_games_are_measured_the_others_say_so(without_solarfox):
    assert list(bench_generic.described_games(["frogs", "zelda", "solarfox"])) == ["frogs", "zelda"]
    section = bench_generic.generic_section(
        ["zelda", "solarfox"], (2,), 0.01, progress=False, modes=("eager",)
    )
    lines = section.text.splitlines()
    row = next(line for line in lines if line.startswith("| zelda | 2 |"))
    hand, generic, share = (cell.strip() for cell in row.split("|")[3:6])
    assert float(hand.split()[0].replace(",", "")) > 0 and float(generic.split()[0].replace(",", "")) > 0
    assert share.endswith("x") and row.endswith("| - | - | - |")
    assert lines[-1] == "No description yet: solarfox." and section.checks == []


def test_a_section_with_no_described_game_is_its_one_line(without_solarfox):
    text = bench_generic.generic_section(["solarfox"], (2,), 0.01, progress=False).text
    assert "| game |" not in text and text.endswith("No description yet: solarfox.\n")


def test_both_engines_play_the_same_game_on_the_same_actions():
    zelda = bench_generic.described_games(["zelda"])["zelda"]
    engines = (bench_generic.get_game("zelda"), bench_generic.generic_game(zelda))
    works = [bench_generic.Ticking(engine, "zelda", 3, "eager", seed=5) for engine in engines]
    for _ in range(20):
        for work in works:
            assert work() == 3
    mine, theirs = (work.state for work in works)
    assert mine.get("score").tolist() == theirs.get("score").tolist()
    assert mine.get("tick").tolist() == theirs.get("tick").tolist() == [22] * 3


def _args(*flags: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    bench.add_arguments(parser)
    return parser.parse_args(list(flags))


def test_the_bench_command_measures_it_on_the_cpu_unless_left_out(monkeypatch):
    calls = []
    monkeypatch.setattr(bench, "generic_section", lambda *args: calls.append(args) or Section("generic\n"))
    assert bench._generic(_args("--games", "zelda,frogs", "--batch-sizes", "2,4"), "cpu").text == "generic\n"
    assert calls == [(["zelda", "frogs"], (2, 4), 2.0)]
    assert bench._generic(_args("--no-generic"), "cpu") == Section()
    assert bench._generic(_args(), "cuda") == Section()


@pytest.mark.slow
def test_the_compiled_ticks_are_measured_too():
    rows = bench_generic.measure_rows(["zelda"], (4,), ("compiled",), min_seconds=0.05, progress=False)
    assert [(row.game, row.batch, row.mode) for row in rows] == [("zelda", 4, "compiled")]
    assert rows[0].ratio > 0
