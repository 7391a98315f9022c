"""What ``GVGAIEnv`` accepts, checked where it comes in: its constructor's arguments and each step's
actions.

A bad input is refused with one ``ValueError`` that names the argument (or the actions and the envs
they were given to) and what would be valid, before anything is allocated or ticked: past this
boundary an out-of-range action indexes the game's tables in a compiled kernel, where it either
plays as another action or aborts the interpreter. The action check costs a few small tensor ops
a step and never waits on an accelerator unless asked to (see ``ActionCheck``).
"""

from __future__ import annotations

import numbers
from collections.abc import Sequence

import numpy as np
import torch

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.games.rng import derive_seeds

OBSERVATION_KINDS = ("tiles", "pixels")

SHOWN = 8  # bad actions (and their envs) named in an error; the count says how many more
# The integer dtypes of action indices (torch's wider unsigned ones lack the ops of the check).
INTEGER_DTYPES = frozenset((torch.uint8, torch.int8, torch.int16, torch.int32, torch.int64))


def is_integer(value: object) -> bool:
    """Whether ``value`` is an integer (Python's or NumPy's), not a bool."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool | np.bool_)


def checked_seeds(seed: object, num_envs: int) -> torch.Tensor:
    """Per-env seeds ``[num_envs]`` int64 from ``seed``: an int (the seeds derived from it) or one
    int per env."""
    if isinstance(seed, torch.Tensor | np.ndarray):
        seed = seed.tolist()
    if is_integer(seed):
        return derive_seeds(int(seed), num_envs)
    if not isinstance(seed, Sequence) or isinstance(seed, str) or not all(map(is_integer, seed)):
        raise ValueError(f"seed must be an int or a list of {num_envs} ints, got {seed!r}")
    if len(seed) != num_envs:
        raise ValueError(f"got {len(seed)} seeds for {num_envs} envs")
    return torch.as_tensor(seed, dtype=torch.int64)


def checked_count(name: str, value: object, minimum: int = 1) -> int:
    """An integer argument (``num_envs``, ``max_steps``, ``shards``) of at least ``minimum``."""
    if not is_integer(value) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def checked_observation_kind(obs: object) -> str:
    """An observation kind: one of ``OBSERVATION_KINDS``."""
    if obs not in OBSERVATION_KINDS:
        raise ValueError(f"unknown observation kind {obs!r}; valid kinds are: {', '.join(OBSERVATION_KINDS)}")
    return obs


def checked_difficulty(value: object) -> float:
    """A difficulty: a real number in [0, 1]."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0.0 <= float(value) <= 1.0:
        raise ValueError(f"difficulty must be a number in [0, 1], got {value!r}")
    return float(value)


def available_devices() -> list[str]:
    """The devices this machine can run the env on: the CPU, then each CUDA device and MPS."""
    devices = ["cpu"]
    if torch.cuda.is_available():
        devices += ["cuda", *(f"cuda:{i}" for i in range(torch.cuda.device_count()))]
    if torch.backends.mps.is_available():
        devices.append("mps")
    return devices


def checked_device(device: object) -> torch.device:
    """``device`` as a ``torch.device`` that exists here (a CUDA device on a machine without
    CUDA would fail later as a bare ``AssertionError`` from torch)."""
    choices = ", ".join(available_devices())
    try:
        parsed = torch.device(device)
    except (RuntimeError, TypeError):
        raise ValueError(f"device {device!r} is not a device; valid devices here are: {choices}") from None
    backend = getattr(torch, parsed.type, None) if parsed.type != "cpu" else None
    is_available = getattr(backend, "is_available", None)
    count = getattr(backend, "device_count", None)
    missing = (is_available is not None and not is_available()) or (
        parsed.index is not None and count is not None and parsed.index >= count()
    )
    if parsed.type == "mps":
        missing = not torch.backends.mps.is_available()
    if missing:
        raise ValueError(
            f"device {device!r} is not available on this machine; valid devices here are: {choices}"
        )
    return parsed


class ActionCheck:
    """Turns a step's ``"action"`` entry into the ``[B]`` int64 action indices the tick takes,
    refusing anything else with one ``ValueError``.

    An action is given per env as an index (``[B]`` or ``[B, 1]``, of dtype int8 to int64 or
    uint8) or one-hot (``[B, A]`` of any dtype, exactly one 1 per row; A is the game's number of
    actions). Indices must lie in ``0 .. A - 1``. Where the actions are on the CPU, whatever the
    env's device, their values are checked on every step (one ``aminmax``, no device sync).
    Actions already on an accelerator are checked there without waiting for it
    (``_private_apis.assert_async``): a bad one stops the process with a device-side assertion,
    since reading the result back would cost a host sync each step. ``strict=True`` reads it back
    and raises the ``ValueError`` there too; ``strict=False`` checks only the shape and dtype.
    """

    def __init__(
        self, num_envs: int, actions: tuple[str, ...], device: torch.device, strict: bool | None = None
    ) -> None:
        self.num_envs, self.names, self.device, self.strict = num_envs, actions, device, strict
        self.num_actions = len(actions)

    @property
    def expected(self) -> str:
        b, a = self.num_envs, self.num_actions
        return (
            f"an action index per env in 0..{a - 1} ({', '.join(self.names)}), of shape [{b}] or [{b}, 1] "
            f"and dtype int8..int64 or uint8, or one-hot of shape [{b}, {a}]"
        )

    def __call__(self, action: torch.Tensor) -> torch.Tensor:
        """The ``[B]`` int64 indices of ``action``, on the env's device."""
        if not isinstance(action, torch.Tensor):
            raise ValueError(f"actions must be a tensor: {self.expected}; got {type(action).__name__}")
        b, a = self.num_envs, self.num_actions
        shape = action.shape
        if (shape == (b,) or shape == (b, 1)) and action.dtype in INTEGER_DTYPES:
            index = action if action.ndim == 1 else action.reshape(b)  # a view costs a few us
            self._check_range(index)
        elif shape == (b, a) and a > 1:
            index = self._one_hot_index(action)
        else:
            raise ValueError(
                f"actions of shape {list(shape)} and dtype {action.dtype}; expected {self.expected}"
            )
        return index.to(self.device, torch.int64)

    def _check_range(self, index: torch.Tensor) -> None:
        """One reduction (``aminmax``) and, on the CPU or where ``strict``, two reads of its result."""
        if self.strict is False:
            return
        low, high = torch.aminmax(index)
        if index.device.type == "cpu" or self.strict:
            if low.item() < 0 or high.item() >= self.num_actions:
                self._refuse(index)
        else:
            assert_async(
                (low >= 0) & (high < self.num_actions), f"an action outside 0..{self.num_actions - 1}"
            )

    def _one_hot_index(self, action: torch.Tensor) -> torch.Tensor:
        if action.dtype.is_complex:
            raise ValueError(f"one-hot actions of dtype {action.dtype}; expected {self.expected}")
        ones, zeros = action == 1, action == 0
        if self.strict is False:
            return ones.to(torch.uint8).argmax(-1)
        bad = (ones.sum(-1) != 1) | ~(ones | zeros).all(-1)
        if action.device.type != "cpu" and not self.strict:
            assert_async(~bad.any(), "a one-hot action without exactly one 1")
        elif bool(bad.any()):
            envs = bad.nonzero().flatten().tolist()
            raise ValueError(
                f"one-hot actions in envs {_listed(envs)} (of {self.num_envs}) do not hold exactly one 1 "
                f"and zeros elsewhere; expected {self.expected}"
            )
        return ones.to(torch.uint8).argmax(-1)

    def _refuse(self, index: torch.Tensor) -> None:
        envs = ((index < 0) | (index >= self.num_actions)).nonzero().flatten()
        raise ValueError(
            f"invalid actions {_listed(index[envs].tolist())} in envs {_listed(envs.tolist())} "
            f"(of {self.num_envs}); expected {self.expected}"
        )


def _listed(values: list) -> str:
    """The first ``SHOWN`` values, then how many more."""
    shown = ", ".join(str(v) for v in values[:SHOWN])
    more = len(values) - SHOWN
    return f"[{shown}{f', ... {more} more' if more > 0 else ''}]"
