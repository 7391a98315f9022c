"""The benchmark harness runs and reports (its numbers are for `make bench`, never asserted)."""

import torch

from gvgai_pcg import benchmark


def test_the_engine_measure_steps_every_game_with_and_without_shards():
    for game in ("zelda", "frogs"):  # frogs: mixed grid sizes are padded like the env pads them
        for shards in (1, 2):
            assert benchmark.measure_engine(game, batch=6, shards=shards, min_seconds=0.0) > 0


def test_the_engine_and_target_tables_have_a_row_per_game(monkeypatch):
    monkeypatch.setattr(benchmark, "ENGINE_BATCH", 8)
    threads = torch.get_num_threads()
    rates = benchmark._engine_rates(["solarfox", "boulderdash"], min_seconds=0.0, progress=False)
    assert torch.get_num_threads() == threads
    lines = benchmark._engine_lines(rates)
    assert lines[-2].startswith("| solarfox | ") and lines[-1].startswith("| boulderdash | ")
    env = [benchmark.StepResult("solarfox", "tiles", 8, 0.0, 300_000.0, 0)]
    targets = benchmark._target_lines(env, {"solarfox": (1.0, 1.0, 1.0), "boulderdash": (2e5, 0, 0)})
    assert targets[-1] == "| solarfox | 250,000 | 1 | no | 300,000 | yes |"
