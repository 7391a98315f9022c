"""The benchmark harness runs and reports (its numbers are for `make bench`, never asserted)."""

import pytest
import torch

from gvgai_pcg.bench import throughput as benchmark
from gvgai_pcg.bench import timing
from gvgai_pcg.envs import GVGAIEnv


def test_the_engine_measure_steps_every_game_with_and_without_shards():
    for game in ("zelda", "frogs"):  # frogs: mixed grid sizes are padded like the env pads them
        for shards in (1, 2):
            rate = benchmark.measure_engine(game, batch=6, shards=shards, min_seconds=0.0)
            assert 0 < rate.low <= rate.median <= rate.high


@pytest.mark.slow
@pytest.mark.compiled
def test_the_engine_measure_runs_the_compiled_ticks_with_and_without_shards():
    for game in ("zelda", "frogs"):
        for shards in (1, 2):
            rate = benchmark.measure_engine(game, batch=6, shards=shards, min_seconds=0.0)
            assert 0 < rate.low <= rate.median <= rate.high


def test_the_engine_and_target_tables_have_a_row_per_game(monkeypatch):
    monkeypatch.setattr(benchmark, "ENGINE_BATCH", 8)
    threads = torch.get_num_threads()
    rates = benchmark._engine_rates(["solarfox", "boulderdash"], min_seconds=0.0, progress=False)
    assert torch.get_num_threads() == threads
    lines = benchmark._engine_lines(rates)
    assert lines[-2].startswith("| solarfox | ") and lines[-1].startswith("| boulderdash | ")
    env = [benchmark.StepResult("solarfox", "tiles", 8, 0.0, benchmark.Rate(300_000, 200_000, 310_000), 0)]
    slow, fast = benchmark.Rate(1, 1, 1), benchmark.Rate(2e5, 2e5, 2e5)
    targets = benchmark._target_lines(env, {"solarfox": (slow,) * 3, "boulderdash": (fast,) * 3})
    assert targets[-1] == "| solarfox | 250,000 | 1 (1) | no | 300,000 (200,000) | yes |"


def test_a_burst_of_load_in_one_window_moves_the_spread_but_not_the_median(monkeypatch):
    clock = iter(range(10_000))  # fake seconds: every perf_counter() call is one second later
    monkeypatch.setattr(timing.time, "perf_counter", lambda: float(next(clock)))
    calls = []

    def step() -> int:
        calls.append(1)
        if len(calls) == 4:  # one step of the second window is stalled by 40 fake seconds
            for _ in range(40):
                next(clock)
        return 10

    rate = benchmark.windowed_rate(step, seconds=15.0, windows=5)
    assert len(calls) >= 15  # at least 3 steps in each window
    assert rate.low < rate.median == rate.high  # only the stalled window is slower


def test_the_env_measure_reports_windows_and_counts_resets():
    result = benchmark.measure_env("frogs", batch=4, obs="tiles", min_seconds=0.0, max_steps=60)
    assert 0 < result.rate.low <= result.steps_per_s <= result.rate.high
    assert result.resets > 0  # random frogs drown within 60 steps


def test_the_env_measure_takes_generated_levels_and_refuses_unknown_sets(monkeypatch):
    from gvgai_pcg.envs.level_sources import GeneratedLevels

    made = []
    monkeypatch.setattr(
        benchmark,
        "GVGAIEnv",
        lambda *args, **kwargs: made.append(kwargs["levels"]) or GVGAIEnv(*args, **kwargs),
    )
    result = benchmark.measure_env(
        "frogs", batch=4, obs="tiles", min_seconds=0.0, max_steps=30, levels="generated"
    )
    assert isinstance(made[0], GeneratedLevels) and result.steps_per_s > 0
    with pytest.raises(ValueError, match="valid ones are: human, generated"):
        benchmark.level_source("frogs", "random")


def test_the_gpu_memory_table_takes_each_games_largest_batch():
    results = [
        benchmark.StepResult("zelda", "tiles", 64, 0.1, benchmark.Rate(1, 1, 1), 0, 64 * 2_000),
        benchmark.StepResult("zelda", "tiles", 4096, 0.1, benchmark.Rate(1, 1, 1), 0, 4096 * 1_000),
        benchmark.StepResult("frogs", "tiles", 1024, 0.1, benchmark.Rate(1, 1, 1), 0, 1024 * 4_000),
    ]
    rows = [line for line in benchmark._memory_lines(results, 2**30) if line.startswith("| ")][1:]
    assert rows == [
        "| zelda | tiles | 4,096 | 4 | 1,000 | 1,073,742 |",
        "| frogs | tiles | 1,024 | 4 | 4,000 | 268,435 |",
    ]


def test_the_benchmarks_page_holds_one_section_per_device_for_make_bench_to_rewrite():
    """``make bench`` rewrites the text between a device's markers in place; a page without them
    would get a second section appended, and its history page must hold none to be rewritten."""
    from pathlib import Path

    docs = Path(__file__).resolve().parents[2] / "docs"
    page, notebook = (
        (docs / "benchmarks.md").read_text(),
        (docs / "history/benchmarks-notebook.md").read_text(),
    )
    for kind in ("cpu", "cuda"):
        start, end = f"<!-- bench:{kind}:start -->", f"<!-- bench:{kind}:end -->"
        assert page.count(start) == page.count(end) == 1 and page.index(start) < page.index(end)
        assert start not in notebook and end not in notebook
