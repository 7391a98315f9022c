"""The one timing loop of the bench: timed windows of repeated work, wall and CPU seconds.

Every measurement here runs some work over and over and reads two clocks around it: wall time
(``time.perf_counter``) and this process's CPU time (``time.process_time``), which a loaded shared
machine disturbs less. A window lasts at least ``seconds / windows`` and at least ``min_calls``
calls; several consecutive windows let a report take their median, so a burst of load from
elsewhere spoils a window, not the figure. One window with a fixed count of calls is how work
alternated with its twin (compiled and eager tick, one and two threads) is timed.

``torch.utils.benchmark.Timer`` was weighed for this and does not fit: it sets torch's thread
count to one unless told otherwise (the bench measures the thread counts themselves), sizes its
blocks by a count calibrated in advance rather than by time, reports seconds per call only, where
the work here says how many env steps a call made (a batch), and reads no CPU time.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass


def synchronize() -> None:
    """Wait for the GPU's queued work, so that a clock read after it counts that work (CUDA runs
    asynchronously; nothing to wait for on the CPU)."""
    import torch

    if torch.cuda.is_available() and torch.cuda.is_initialized():
        torch.cuda.synchronize()


class Stopwatch:
    """Adds up the wall and CPU seconds spent inside its ``with`` blocks; with ``sync``, each block
    waits for the GPU's queued work at its end (which keeps timed parts apart but keeps them
    from overlapping)."""

    def __init__(self, sync: bool = False) -> None:
        self.wall = self.cpu = 0.0
        self.sync = sync

    def __enter__(self) -> Stopwatch:
        self._start, self._cpu = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.sync:
            synchronize()
        self.wall += time.perf_counter() - self._start
        self.cpu += time.process_time() - self._cpu

    def reset(self) -> None:
        self.wall = self.cpu = 0.0

    @property
    def cores(self) -> float:
        """CPU seconds per wall second: how many cores the timed work kept busy."""
        return self.cpu / self.wall if self.wall > 0 else 0.0


@dataclass(frozen=True)
class Window:
    """One timed window: how much work was done (what ``work`` returned, summed: env steps, or
    calls), in how many calls, and the seconds it took."""

    units: int
    calls: int
    wall: float
    cpu: float

    @property
    def rate(self) -> float:
        """Units per wall second."""
        return self.units / self.wall


def time_windows(
    work: Callable[[], int],
    seconds: float,
    windows: int = 1,
    min_calls: int = 1,
    max_calls: int | None = None,
    sync: bool = False,
) -> list[Window]:
    """Time ``windows`` consecutive windows of calls of ``work`` (which returns how many units it
    did), each at least ``seconds / windows`` wall seconds and ``min_calls`` calls, and at most
    ``max_calls`` calls where given. With ``sync``, the GPU's queued work is waited for at each
    window's start and end."""
    timed = []
    for _ in range(windows):
        if sync:
            synchronize()
        calls, units = 0, 0
        begin, cpu = time.perf_counter(), time.process_time()
        while calls < min_calls or (time.perf_counter() - begin < seconds / windows and calls != max_calls):
            units += work()
            calls += 1
        if sync:
            synchronize()
        timed.append(Window(units, calls, time.perf_counter() - begin, time.process_time() - cpu))
    return timed
