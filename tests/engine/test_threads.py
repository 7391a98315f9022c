"""Torch threads come from the batch and the idle cores: one thread wherever a second would wait
on a core another process holds, or have no envs to split."""

import pytest

from gvgai_pcg.engine import threads
from gvgai_pcg.engine.threads import MIN_ENVS_PER_THREAD, idle_cores, threads_for_batch


@pytest.mark.parametrize(
    ("envs", "idle", "expected"),
    [
        (12, 2, 1),
        (64, 2, 1),  # a quiet machine, but too few envs for a second thread
        (MIN_ENVS_PER_THREAD * 2 - 1, 2, 1),
        (MIN_ENVS_PER_THREAD * 2, 2, 2),
        (4096, 2, 2),
        (4096, 1, 1),  # one core taken: two threads made 0.07x of one at 4,096 envs
        (4096, 0, 1),
        (65536, 16, 16),
    ],
)
def test_threads_follow_the_batch_and_the_idle_cores(envs, idle, expected):
    assert threads_for_batch(envs, idle) == expected


def test_idle_cores_leave_out_the_load_of_other_work(monkeypatch):
    monkeypatch.setattr(threads.os, "getloadavg", lambda: (1.2, 0.0, 0.0))
    assert idle_cores(4) == 2  # a core partly taken counts as taken
    monkeypatch.setattr(threads.os, "getloadavg", lambda: (9.0, 0.0, 0.0))
    assert idle_cores(2) == 0 and threads_for_batch(4096) == 1
    monkeypatch.setattr(threads.os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert idle_cores(2) == 2


def test_training_with_threads_0_takes_the_rule(monkeypatch):
    from gvgai_pcg.rl import training

    asked, set_to = [], []
    monkeypatch.setattr(training, "threads_for_batch", lambda envs: asked.append(envs) or 3)
    monkeypatch.setattr(training.torch, "set_num_threads", set_to.append)
    monkeypatch.setattr(training, "open_run", lambda *args: (_ for _ in ()).throw(RuntimeError("stop")))
    from gvgai_pcg.config import compose_config

    cfg = compose_config(["threads=0", "env.num_envs=12"])
    with pytest.raises(RuntimeError, match="stop"):
        training.train(cfg, None)
    assert asked == [12] and set_to == [3]
