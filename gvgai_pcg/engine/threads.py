"""How many torch threads a process stepping a batch of envs should use: ``threads_for_batch``.

torch's intra-op threads (OpenMP) wait for each other at the end of every op. Where another process
holds a core, the second thread is preempted and every op of the step waits for it, so two threads
make a small fraction of one thread's steps/s at every batch. Zelda, tiles, human levels, one env
per batch alternating one and two threads (four windows of 2.5 s each, ``nice -n 10``), on 2
cores that two training runs and other jobs kept busy (load average 10-11; docs/history/
benchmarks-notebook.md, "One step plan per env, threads by batch"):

    envs    1 thread    2 threads   2/1
    64      8,692       556         0.06
    1,024   45,716      5,575       0.12
    4,096   89,711      6,411       0.07

(``nice -n 10 python -m gvgai_pcg.bench.threads zelda 64 1024 4096``.) A second thread pays only
on a core nobody else uses, and only where the tick has work to split: the compiled tick's loops
over the envs run in parallel from ``LARGE_BATCH_PER_THREAD`` (512) envs a thread (inductor's
minimum chunk; below it they are serial whatever the threads), and on a quiet machine two threads
stepped Zelda's engine at 4,096 envs at 1.98M steps/s against 1.25M on one
(docs/history/benchmarks-notebook.md, "CPU").
So: one thread below that many envs a thread, and never more threads than cores left idle by
other work.
"""

from __future__ import annotations

import os

from gvgai_pcg.engine.compiled import LARGE_BATCH_PER_THREAD

# The crossover: a thread needs at least this many envs of the batch to gain anything.
MIN_ENVS_PER_THREAD = LARGE_BATCH_PER_THREAD


def idle_cores(cores: int | None = None) -> int:
    """Cores that other work leaves idle: the cores less the last minute's load average (rounded
    up: a core half taken preempts a thread as surely as a full one)."""
    cores = (os.cpu_count() or 1) if cores is None else cores
    busy = os.getloadavg()[0] if hasattr(os, "getloadavg") else 0.0
    return max(0, cores - int(-(-busy // 1)))


def threads_for_batch(num_envs: int, idle: int | None = None) -> int:
    """Torch threads for stepping ``num_envs`` envs with ``idle`` cores free (by default
    ``idle_cores()``, read now): one, unless every thread gets at least ``MIN_ENVS_PER_THREAD``
    envs and a core of its own."""
    idle = idle_cores() if idle is None else idle
    return max(1, min(idle, num_envs // MIN_ENVS_PER_THREAD))
