"""The thread-count script alternates its counts window by window and gives the threads back (its
numbers are for reading, never asserted)."""

import torch

from gvgai_pcg.bench.threads import measure_threads


def test_the_thread_script_times_each_count_in_every_window_and_restores_the_threads():
    before = torch.get_num_threads()
    rates = measure_threads("zelda", batch=3, windows=2, window_s=0.0)
    assert set(rates) == {1, 2} and all(len(r) == 2 and min(r) > 0 for r in rates.values())
    assert torch.get_num_threads() == before
