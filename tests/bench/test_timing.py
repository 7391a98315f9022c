"""The bench's one timing loop: how many calls a window makes, what it adds up (on a fake clock,
so nothing here depends on the machine's speed)."""

from gvgai_pcg.bench import timing


def _fake_clock(monkeypatch) -> None:
    """Every read of either clock is one second later than the last read of that clock."""
    walls, cpus = iter(range(100_000)), iter(range(0, 200_000, 2))
    monkeypatch.setattr(timing.time, "perf_counter", lambda: float(next(walls)))
    monkeypatch.setattr(timing.time, "process_time", lambda: float(next(cpus)))


def test_a_window_makes_its_least_calls_then_runs_until_its_share_of_the_seconds(monkeypatch):
    _fake_clock(monkeypatch)
    calls = []
    windows = timing.time_windows(lambda: calls.append(1) or 4, seconds=20.0, windows=2, min_calls=3)
    assert len(windows) == 2 and all(w.calls >= 3 for w in windows)
    assert all(w.wall >= 10.0 for w in windows)  # each window: at least 20 / 2 fake seconds
    assert sum(w.calls for w in windows) == len(calls)
    assert all(w.units == 4 * w.calls and w.rate == w.units / w.wall for w in windows)


def test_a_window_stops_at_its_cap_and_at_once_when_the_seconds_are_zero(monkeypatch):
    _fake_clock(monkeypatch)
    capped = timing.time_windows(lambda: 1, seconds=1_000.0, windows=3, min_calls=2, max_calls=5)
    assert [w.calls for w in capped] == [5, 5, 5]
    (counted,) = timing.time_windows(lambda: 7, seconds=0.0, min_calls=11)
    assert (counted.calls, counted.units) == (11, 77)


def test_the_stopwatch_adds_up_its_blocks_and_counts_cores(monkeypatch):
    _fake_clock(monkeypatch)
    watch = timing.Stopwatch()
    with watch:
        pass
    with watch:
        pass
    assert (watch.wall, watch.cpu, watch.cores) == (2.0, 4.0, 2.0)  # the fake CPU clock runs twice as fast
    watch.reset()
    assert (watch.wall, watch.cpu, watch.cores) == (0.0, 0.0, 0.0)
