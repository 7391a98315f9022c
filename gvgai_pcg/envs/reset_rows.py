"""Merging a partial reset into the running tensordict by rows, not by ``torch.where``.

After a partial reset TorchRL merges the reset output into the running tensordict with
``torch.where`` over every entry. On the CPU a ``where`` whose mask is broadcast over an
observation is slow: for the uint8 tiles of thousands of envs it costs more than the step itself,
and it is paid on every step that ends an episode somewhere in the batch. Copying just the reset
rows gives the same tensordict at a small fraction of that cost. Anything but a plain ``"_reset"``
mask goes to TorchRL's own merge. The TorchRL internals this takes over and calls back into are
wrapped in :mod:`gvgai_pcg._private_apis`.
"""

from __future__ import annotations

from functools import partial

import torch
from tensordict import TensorDict, TensorDictBase
from torchrl.envs import EnvBase, TransformedEnv

from gvgai_pcg._private_apis import (
    ResetMergeHook,
    allows_done_after_reset,
    complete_done,
    entries,
    reset_check_done,
    torchrl_reset_merge,
)
from gvgai_pcg.engine.buffers import BufferPool
from gvgai_pcg.engine.rows import copy_tensor_rows_

RESET_KEY = "_reset"


def merge_reset_rows(
    tensordict_reset: TensorDictBase,
    tensordict: TensorDictBase,
    reset_keys: list,
    pool: BufferPool | None = None,
    complete: dict | None = None,
) -> TensorDictBase:
    """``tensordict`` with the rows that ``"_reset"`` marks taken from ``tensordict_reset``, as
    TorchRL's merge leaves it: an entry missing on one side counts as zeros there. The entries are
    replaced, never written in place (they may be shared with the step's ``"next"`` data); they
    are copied into buffers from ``pool`` if one is given. ``complete`` maps keys to entries of
    ``tensordict_reset`` that already hold the running values outside the marked rows; such an
    entry, if still there, is taken whole instead of copied."""
    reset = tensordict.get(RESET_KEY, None) if list(reset_keys) == [RESET_KEY] else None
    if reset is None or reset.ndim > tensordict.ndim + 1 or tensordict.ndim != 1:
        return torchrl_reset_merge(tensordict_reset, tensordict, reset_keys)
    tensordict.pop(RESET_KEY)
    rows = reset.reshape(tensordict.shape).nonzero().squeeze(-1)  # the merge's one host sync
    if len(rows) == tensordict.numel():
        return tensordict.update(tensordict_reset.exclude(RESET_KEY), update_batch_size=True)
    complete = complete or {}
    plain = type(tensordict) is TensorDict and type(tensordict_reset) is TensorDict
    ours, theirs = (entries(tensordict), entries(tensordict_reset)) if plain else ({}, {})
    if not plain or any(isinstance(value, TensorDictBase) for value in (*ours.values(), *theirs.values())):
        fresh = tensordict_reset.exclude(RESET_KEY)  # nested: by key paths
        keys = set(fresh.keys(True, True)) | set(tensordict.keys(True, True))
        read_old, read_new = partial(tensordict.get, default=None), partial(fresh.get, default=None)
    else:  # flat, as GVGAIEnv's: straight from the entry dicts, which cost a fraction of get
        keys = (set(ours) | set(theirs)) - {RESET_KEY}
        read_old, read_new = ours.get, theirs.get
    for key in keys:
        old, new = read_old(key), read_new(key)
        if new is None:
            tensordict.set(key, old.index_fill(0, rows, 0))
        elif new is complete.get(key):
            tensordict.set(key, new)
        else:
            base = torch.zeros_like(new) if old is None else old.clone() if pool is None else pool.clone(old)
            tensordict.set(key, copy_tensor_rows_(base, rows, new.index_select(0, rows)))
    return tensordict


def check_reset_not_done(env: EnvBase, tensordict: TensorDictBase, tensordict_reset: TensorDictBase) -> None:
    """TorchRL's check that no env a ``"_reset"`` mask restarts is done after it
    (:func:`gvgai_pcg._private_apis.reset_check_done`), for a plain mask over a tensordict that has
    every done entry (a collector's case) in a few ops; any other case goes to TorchRL's own check,
    whose indexing by the mask costs more."""
    reset = tensordict.get(RESET_KEY, None) if list(env.reset_keys) == [RESET_KEY] else None
    done_keys = list(env.done_keys)
    if (
        reset is None
        or tensordict.ndim != 1
        or any(tensordict.get(key, None) is None for key in done_keys)
        or any(tensordict_reset.get(key).shape != reset.shape for key in done_keys)
    ):
        reset_check_done(env, tensordict, tensordict_reset)
        return
    if allows_done_after_reset(env):
        return
    done_after = [tensordict_reset.get(key) & reset for key in done_keys]
    if not torch.stack(done_after).any():  # one host sync for every done entry
        return
    key = next(key for key, done in zip(done_keys, done_after, strict=True) if done.any())
    raise RuntimeError(
        f"Env done entry '{key}' was (partially) True after reset on specified '_reset' "
        "dimensions. This is not allowed."
    )


def take_complete_entries(env: EnvBase) -> dict | None:
    """The complete entries (see :class:`RowResetEnv`) of ``env``'s last reset output, once."""
    complete = getattr(env, "_complete_entries", None)
    if complete is not None:
        env._complete_entries = None
    return complete


class OneReadMaybeReset:
    """Mixin for an ``EnvBase`` (or ``TransformedEnv``) whose done entries are a root ``"done"``
    and ``"terminated"`` (TorchRL's "simple done"): ``maybe_reset`` reads ``"done"``'s ``any()``
    back once, where TorchRL's ``any_done`` and ``maybe_reset`` each convert it to a bool (two
    host syncs a step on an accelerator). Same result: where some env is done, ``"_reset"`` is a
    copy of ``"done"`` and the env resets them; other done layouts go to TorchRL's own."""

    def maybe_reset(self, tensordict: TensorDictBase) -> TensorDictBase:
        done_keys = self.done_keys
        if "done" not in done_keys or "terminated" not in done_keys:
            return super().maybe_reset(tensordict)
        done = tensordict.get("done", None)
        if done is None or not done.any():
            return tensordict
        tensordict.set(RESET_KEY, done.clone())
        return self.reset(tensordict, select_reset_only=True)


class RowResetEnv(OneReadMaybeReset, ResetMergeHook, EnvBase):
    """An ``EnvBase`` whose partial resets are merged by :func:`merge_reset_rows`.

    A subclass whose ``_reset`` output holds the running values in the rows it does not reset
    may say which of its entries do, as ``_complete_entries`` (key to tensor); the merge takes
    those whole, as long as they are still the output's entries. An entry replaced after
    ``_reset`` (by a subclass or a transform) is merged by rows as TorchRL would.
    """

    _complete_entries: dict | None = None
    # True where every ``_reset`` output holds every done entry of the spec, in the spec's shape:
    # then TorchRL's completion of the done entries (some 40 us a reset at 64 envs) is skipped,
    # unless the env runs type checks (as ``CompleteStepHook`` skips it for a step).
    complete_reset_outputs: bool = False

    def merge_reset(self, tensordict, tensordict_reset):
        if not self.complete_reset_outputs or self.run_type_checks:
            complete_done(self, tensordict_reset)
        complete = take_complete_entries(self)
        if tensordict is None:
            reset_check_done(self, tensordict, tensordict_reset)
            return tensordict_reset
        check_reset_not_done(self, tensordict, tensordict_reset)
        pool = getattr(self, "buffers", None)
        return merge_reset_rows(tensordict_reset, tensordict, self.reset_keys, pool, complete)


class RowResetTransformedEnv(OneReadMaybeReset, ResetMergeHook, TransformedEnv):
    """A ``TransformedEnv`` whose partial resets are merged by :func:`merge_reset_rows` (entries
    the transforms left as the base env's complete ones are taken whole)."""

    def merge_reset(self, tensordict, tensordict_reset):
        complete = take_complete_entries(self.base_env)
        if tensordict is None:
            reset_check_done(self, tensordict, tensordict_reset)
        else:
            check_reset_not_done(self, tensordict, tensordict_reset)
            pool = getattr(self.base_env, "buffers", None)
            tensordict_reset = merge_reset_rows(tensordict_reset, tensordict, self.reset_keys, pool, complete)
        return tensordict_reset
