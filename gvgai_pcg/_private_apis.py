"""Every private API of torch, tensordict and TorchRL that gvgai_pcg uses, and why.

Each is wrapped here in a small function (or, for a hook TorchRL calls on a subclass, a mixin)
with a public name, and no other module of the package names it (tests/test_private_apis.py
checks that). An upgrade may change any of them without notice, so that test file also checks
each one's signature and the behaviour relied on here, and fails naming the API and the version
the package pins (pyproject.toml: torch 2.13.0, torchrl 0.14.x, tensordict 0.14.x). When one
fails after an upgrade, fix the function here; its callers need not change.

* ``torch._C._storage_Use_Count``: how many tensors share a storage. :class:`BufferPool`
  (engine/buffers.py) hands a kept buffer out again only when nothing else uses it; without this
  count it just allocates (:data:`HAS_STORAGE_USE_COUNT`).
* ``torch._assert_async``: a check on a tensor that raises without syncing the device in the
  step (Frogs' log table is never full when a spawner fires).
* ``TensorDict._new_unsafe``: builds a TensorDict without validating its entries, for states cut
  row by row from a valid one (engine/rows.py), where the checks would cost more than the cut.
* ``TensorDict._tensordict``: the dict of a TensorDict's entries, read by a partial reset's merge
  of a few rows (envs/states.py), where ``get`` and ``items`` cost more than the copies, and
  written by the generic VGDL step (vgdl/engine/frame.py), which writes back the fields its tick
  changed, each of the entry's own shape and dtype, where ``update``'s checks cost a fifth of
  an eager tick.
* ``EnvBase._step_proc_data`` (a hook): TorchRL reshapes a step's rewards and fills its missing
  done entries; ``GVGAIEnv``'s steps have neither to do, and it skips the checks
  (:class:`CompleteStepHook`).
* ``EnvBase._reset_proc_data`` (a hook), ``EnvBase._reset_check_done``, ``EnvBase._complete_done``,
  ``EnvBase._allow_done_after_reset`` and ``torchrl.envs.utils._update_during_reset``: TorchRL
  merges a partial reset into the running tensordict with ``torch.where`` over every entry; the
  envs (envs/reset_rows.py) take over that step to copy just the reset rows, and call back into
  TorchRL's own checks and merge for every case they do not handle.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
from tensordict import TensorDict, TensorDictBase

PINNED = "torch 2.13.0, torchrl 0.14.x, tensordict 0.14.x (pyproject.toml)"

# --- torch ---------------------------------------------------------------------------------------

_storage_use_count = getattr(torch._C, "_storage_Use_Count", None)
HAS_STORAGE_USE_COUNT = _storage_use_count is not None


def storage_use_count(storage: torch.UntypedStorage) -> int:
    """How many tensors (and arrays sharing their memory) use ``storage``, by
    ``torch._C._storage_Use_Count``. Only where :data:`HAS_STORAGE_USE_COUNT`."""
    return _storage_use_count(storage._cdata)


def assert_async(condition: torch.Tensor, message: str) -> None:
    """Raise ``RuntimeError(message)`` where the bool tensor ``condition`` (one element) is false,
    without a host sync on an accelerator (``torch._assert_async``; on the CPU it raises at once)."""
    torch._assert_async(condition, message)


# --- tensordict ----------------------------------------------------------------------------------


def unchecked_tensordict(
    values: dict[str, torch.Tensor | TensorDictBase], batch_size: Sequence[int], device: torch.device | None
) -> TensorDict:
    """``TensorDict(values, batch_size, device)`` without validating the entries
    (``TensorDict._new_unsafe``): the caller guarantees every entry has ``batch_size`` as its
    leading dims and lives on ``device``. The entries are taken as they are, not copied."""
    return TensorDict._new_unsafe(values, batch_size=batch_size, device=device)


def write_entries(tensordict: TensorDict, values: dict[str, torch.Tensor]) -> None:
    """Replace entries of ``tensordict`` by ``values`` without validating them
    (``TensorDict._tensordict``): the caller guarantees each keeps its entry's shape, dtype and
    device."""
    tensordict._tensordict.update(values)


def entries(tensordict: TensorDict) -> dict[str, torch.Tensor | TensorDict]:
    """The entries of ``tensordict`` (one level, not its nested ones' leaves) as the dict it keeps
    them in (``TensorDict._tensordict``), to read and not to change: a ``get`` or ``items`` goes
    through key checks that cost more than the copy a partial reset makes of each of a few rows."""
    return tensordict._tensordict


# --- TorchRL's reset internals -------------------------------------------------------------------


class ResetMergeHook:
    """Mixin for an ``EnvBase`` (or ``TransformedEnv``) subclass: TorchRL's ``reset`` ends by
    returning ``self._reset_proc_data(tensordict, tensordict_reset)``, which completes the done
    entries, checks them and merges a partial reset into the running tensordict. With this mixin
    first among the bases, that step is the subclass's ``merge_reset`` (same arguments, same
    return value). A ``TransformedEnv`` runs only its own hook, not its base env's."""

    def _reset_proc_data(self, tensordict: TensorDictBase | None, tensordict_reset: TensorDictBase):
        return self.merge_reset(tensordict, tensordict_reset)

    def merge_reset(
        self, tensordict: TensorDictBase | None, tensordict_reset: TensorDictBase
    ) -> TensorDictBase:
        raise NotImplementedError


class CompleteStepHook:
    """Mixin for an ``EnvBase`` subclass whose ``_step`` output is always complete: the reward
    has the spec's shape and every done entry of the spec is there. TorchRL's ``step`` passes that
    output through ``self._step_proc_data``, which reshapes the rewards and fills missing done
    entries: for a complete output, some 40 us of checks a step (a twentieth of a step of 64 Zelda
    envs). With this mixin first among the bases the output is taken as it is, unless the env
    runs type checks (``run_type_checks``), which TorchRL's own does."""

    def _step_proc_data(self, next_tensordict_out: TensorDictBase) -> TensorDictBase:
        if self.run_type_checks:
            return super()._step_proc_data(next_tensordict_out)
        return next_tensordict_out


def complete_done(env, tensordict_reset: TensorDictBase) -> None:
    """Fill the done entries ``env``'s spec declares but ``tensordict_reset`` lacks, in place, as
    TorchRL's reset does first (``EnvBase._complete_done``)."""
    env._complete_done(env.full_done_spec, tensordict_reset)


def reset_check_done(env, tensordict: TensorDictBase | None, tensordict_reset: TensorDictBase) -> None:
    """TorchRL's check that no env a reset restarted is done after it
    (``EnvBase._reset_check_done``): raises ``RuntimeError`` if one is, unless ``env`` allows it."""
    env._reset_check_done(tensordict, tensordict_reset)


def allows_done_after_reset(env) -> bool:
    """Whether ``env`` was made with ``allow_done_after_reset`` (``EnvBase._allow_done_after_reset``)."""
    return getattr(env, "_allow_done_after_reset", False)


def torchrl_reset_merge(
    tensordict_reset: TensorDictBase, tensordict: TensorDictBase, reset_keys: list
) -> TensorDictBase:
    """TorchRL's own merge of a partial reset (``torchrl.envs.utils._update_during_reset``):
    ``tensordict`` with the rows its reset keys mark taken from ``tensordict_reset``, by
    ``torch.where``; the reset keys are popped. TorchRL is imported here only when needed, so
    that the games, which use the rest of this module, do not load it."""
    from torchrl.envs.utils import _update_during_reset

    return _update_during_reset(tensordict_reset, tensordict, reset_keys)
