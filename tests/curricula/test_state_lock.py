"""The lock around a curriculum's shared state excludes other processes (``shared_buffers.exclusive``)."""

from __future__ import annotations

import multiprocessing
import time
from pathlib import Path

from gvgai_pcg.envs.shared_buffers import exclusive


def _add_one_many_times(counter: Path, lock: Path, times: int) -> None:
    for _ in range(times):
        with exclusive(lock):
            value = int(counter.read_text())
            time.sleep(0.0005)  # widen the window a missing lock would let another process into
            counter.write_text(str(value + 1))


def test_two_processes_never_interleave_inside_the_lock(tmp_path):
    counter, lock = tmp_path / "counter", tmp_path / "state.lock"
    counter.write_text("0")
    context = multiprocessing.get_context("fork")
    workers = [context.Process(target=_add_one_many_times, args=(counter, lock, 100)) for _ in range(2)]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join(60)
    assert [worker.exitcode for worker in workers] == [0, 0]
    assert int(counter.read_text()) == 200  # a lost update means two were inside at once
    assert lock.exists()  # kept on release: a waiter's open file stays the lock


def test_no_path_means_no_lock():
    with exclusive(None):
        pass


def test_a_kept_lock_is_entered_again_and_travels_to_workers(tmp_path):
    import pickle

    lock = exclusive(tmp_path / "state.lock")
    for _ in range(2):  # a shared state keeps one lock for every move
        with lock:
            assert lock._held
        assert not lock._held
    with lock:
        copy = pickle.loads(pickle.dumps(lock))  # a worker's copy holds nothing of the parent's
    assert copy.path == lock.path and copy._held == []
    with copy:
        pass
