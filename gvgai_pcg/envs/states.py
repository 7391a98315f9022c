"""Batched game states as the env moves them around: partial resets merge fresh envs into the
running state, and the level bank keeps many compiled envs in one batch.

Env plumbing, not rules: a game only compiles levels into a state and ticks it
(``gvgai_pcg.games.base``). Entity tables of two states may have different slot counts; both
operations grow the smaller ones with empty (zero) slots, as padding would give them.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import torch
from tensordict import TensorDict

from gvgai_pcg._private_apis import entries, unchecked_tensordict
from gvgai_pcg.engine.rows import copy_tensor_rows_


def merge_states(
    state: TensorDict,
    fresh: TensorDict,
    index: torch.Tensor,
    round_up: bool = False,
    fresh_rows: torch.Tensor | None = None,
) -> TensorDict:
    """``state`` with envs ``index`` replaced by ``fresh`` (a partial reset), or by rows
    ``fresh_rows`` of ``fresh`` if given (taken entry by entry, with no state of their own built
    first). An entity table of ``state`` is grown where ``fresh`` has more slots (with
    ``round_up``, to a power of two: a compiled tick recompiles for every table width it meets,
    gvgai_pcg.engine.compiled); where it has fewer, the fresh rows get empty slots (zeros, as
    padding would give them) leaf by leaf, which costs a fraction of padding the fresh tables as
    TensorDicts."""
    ours, theirs = entity_capacities(state), entity_capacities(fresh)
    width = slot_bucket if round_up else int
    grown = {key: width(theirs[key]) for key in ours if theirs[key] > ours[key]}
    state = pad_entity_tables(state, grown)
    _merge_rows(state, fresh, index, fresh_rows, tables=set(ours))
    return state


def _merge_rows(
    state: TensorDict,
    fresh: TensorDict,
    index: torch.Tensor,
    fresh_rows: torch.Tensor | None,
    tables: set[str] | None = None,
) -> None:
    """The row copies of :func:`merge_states`, table by table: a nested TensorDict's ``get`` by
    key path costs several times a plain key's, which was most of a one-env merge. Leaves of the
    entity tables (``tables``; inside one, ``None``: every leaf) with fewer slots than ``state``'s
    get empty ones."""
    targets = entries(state)
    for key, value in entries(fresh).items():
        target = targets[key]
        in_table = tables is None or key in tables
        if isinstance(value, TensorDict):
            _merge_rows(target, value, index, fresh_rows, None if in_table else set())
            continue
        if fresh_rows is not None:
            value = value.index_select(0, fresh_rows)
        if in_table and value.ndim > 1 and value.shape[1] < target.shape[1]:
            value = grow_slots(value, target.shape[1] - value.shape[1])
        copy_tensor_rows_(target, index, value)


def slot_bucket(slots: int) -> int:
    """The smallest power of two that holds ``slots`` entity slots, at least 2: a compiled tick
    specialises tables of 0 and 1 slots (each its own compilation, seconds each)."""
    return max(2, 1 << max(0, slots - 1).bit_length())


def bucket_entity_tables(state: TensorDict) -> TensorDict:
    """``state`` with every entity table grown to its :func:`slot_bucket` (empty slots), so that a
    compiled tick meets few table widths."""
    sizes = entity_capacities(state)
    return pad_entity_tables(state, {key: slot_bucket(size) for key, size in sizes.items()})


def concatenate_states(states: Sequence[TensorDict]) -> TensorDict:
    """One batch of the envs of ``states`` (in order); entity tables are grown to the largest."""
    sizes: dict[str, int] = {}
    for state in states:
        for key, size in entity_capacities(state).items():
            sizes[key] = max(size, sizes.get(key, 0))
    return torch.cat([pad_entity_tables(state.clone(False), sizes) for state in states], dim=0)


def pad_entity_tables(state: TensorDict, capacities: dict[str, int]) -> TensorDict:
    """``state`` with each entity table named in ``capacities`` grown to that many slots."""
    for key, size in capacities.items():
        table = state.get(key)
        missing = size - table.batch_size[1]
        if missing > 0:
            # Leaf by leaf into an unchecked TensorDict: a TensorDict ``cat`` validates every
            # entry and costs much more, and ``apply`` a third more (Frogs' one-env reset: 240
            # against 378 us).
            grown = {
                name: grow_slots(value, missing)
                if isinstance(value, torch.Tensor)
                else pad_rows_of(value, missing)
                for name, value in table.items()
            }
            state.set(key, unchecked_tensordict(grown, torch.Size([len(table), size]), table.device))
    return state


def pad_rows_of(table: TensorDict, missing: int) -> TensorDict:
    """A table nested in an entity table, its leaves grown by ``missing`` zero slots."""
    return table.apply(
        functools.partial(grow_slots, missing=missing), batch_size=[len(table), table.batch_size[1] + missing]
    )


def grow_slots(tensor: torch.Tensor, missing: int) -> torch.Tensor:
    """``tensor [B, K, ...]`` with ``missing`` zero slots appended along ``K``."""
    return torch.cat([tensor, tensor.new_zeros((tensor.shape[0], missing, *tensor.shape[2:]))], dim=1)


def entity_capacities(state: TensorDict) -> dict[str, int]:
    """The slot count of every entity table (nested TensorDict with a ``[B, K]`` batch)."""
    return {
        key: value.batch_size[1]
        for key, value in state.items()
        if isinstance(value, TensorDict) and value.batch_dims == 2
    }
