"""Stepping a CPU batch as contiguous shards, one Python thread each (opt-in).

PyTorch's intra-op threads (OpenMP) split every large op across the cores, which is the fastest
way to step a batch on a quiet machine (docs/benchmarks.md). Where cores are shared, OpenMP's
synchronised thread teams stall whenever one of their threads is preempted: on a busy 2-core VM,
two shards of B/2 envs, each ticked and rendered on its own Python thread with one torch thread,
stepped Boulderdash at B = 4096 about twice as fast as two intra-op threads. PyTorch releases
the GIL inside every op, so the shards overlap as long as their ops are long next to their
Python dispatch.

Every env depends only on its own row of the state (the RNG is a counter hash of the env's own
seed), so a sharded step gives exactly the state and observation of an unsharded one.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import torch
from tensordict import TensorDict

StepFn = Callable[[TensorDict, torch.Tensor], torch.Tensor]


class ShardedStepper:
    """Runs ``step(state, action) -> observation`` on up to ``shards`` contiguous slices of a
    batch, one env at least each (whoever asks for shards has chosen them for the batch).

    ``step`` may replace the entries of the state it is given (games ``update`` them); each
    shard's replaced entries are copied back into the full state by its own thread, so no two
    entries of the full state may share memory (tested for every game).
    """

    def __init__(self, shards: int) -> None:
        if shards < 1:
            raise ValueError(f"shards must be at least 1, got {shards}")
        self.shards = shards
        self._pool = None
        if shards > 1:
            self._pool = ThreadPoolExecutor(shards, thread_name_prefix="gvgai-shard")
            weakref.finalize(self, self._pool.shutdown, wait=False)

    def slices(self, num_envs: int) -> list[slice]:
        count = max(1, min(self.shards, num_envs))
        bounds = [num_envs * k // count for k in range(count + 1)]
        return [slice(a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True)]

    def __call__(self, step: StepFn, state: TensorDict, action: torch.Tensor) -> torch.Tensor:
        slices = self.slices(state.batch_size[0])
        if len(slices) == 1:
            return step(state, action)
        threads = torch.get_num_threads()

        def run(rows: slice) -> torch.Tensor:
            torch.set_num_threads(1)  # this thread's ops; the caller's setting is restored below
            part = state[rows]  # views into the full state
            originals = list(part.items(True, True))  # kept alive, so their ids stay unique
            views = {id(value): key for key, value in originals}
            observation = step(part, action[rows])
            _write_back(state, part, views, rows)
            del originals
            return observation

        try:
            observations = list(self._pool.map(run, slices))
        finally:
            torch.set_num_threads(threads)
        return torch.cat(observations)


def _write_back(state: TensorDict, part: TensorDict, views: dict[int, object], rows: slice) -> None:
    """Copy the entries a step replaced in ``part`` into ``state[rows]``.

    Entries still holding their own view were updated in place (or not at all). A view that the
    step moved to another key (Zelda keeps the old position as ``lastx``) still shows the old
    values only until its own key is written, so such values are cloned before anything is copied.
    """
    pending = []
    for key, value in part.items(True, True):
        origin = views.get(id(value))
        if origin == key:
            continue
        pending.append((key, value if origin is None else value.clone()))
    for key, value in pending:
        state.get(key)[rows].copy_(value)
