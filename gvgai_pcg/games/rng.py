"""Counter-based randomness: a uniform number is a pure function of
(episode seed, tick, entity slot, stream).

This is what makes an environment's trajectory independent of the batch it shares and of the
device: no generator state is carried or advanced, so B envs stepped together draw exactly
what each would draw alone. The mixer is SplitMix64's finaliser, done in int64 arithmetic
(wrapping multiplication; logical shifts emulated with masks).
"""

from __future__ import annotations

import torch

_MASK64 = (1 << 64) - 1


def _signed(value: int) -> int:
    value &= _MASK64
    return value - (1 << 64) if value >= 1 << 63 else value


_GOLDEN = _signed(0x9E3779B97F4A7C15)
_MIX1 = _signed(0xBF58476D1CE4E5B9)
_MIX2 = _signed(0x94D049BB133111EB)
_KEY_TICK = _signed(0xD1B54A32D192ED03)
_KEY_SLOT = _signed(0xABC98388FB8FAC03)
_KEY_STREAM = _signed(0x8CB92BA72F3D8DD7)


def _shift_right(x: torch.Tensor, bits: int) -> torch.Tensor:
    """Logical right shift of int64 values."""
    return (x >> bits) & ((1 << (64 - bits)) - 1)


def mix64(x: torch.Tensor) -> torch.Tensor:
    """SplitMix64 finaliser on int64 tensors (bijective, well mixed)."""
    x = x + _GOLDEN
    x = (x ^ _shift_right(x, 30)) * _MIX1
    x = (x ^ _shift_right(x, 27)) * _MIX2
    return x ^ _shift_right(x, 31)


def hash_bits(seed: torch.Tensor, tick: torch.Tensor, slot: torch.Tensor | int, stream: int) -> torch.Tensor:
    """64 random bits per element, a function of its arguments only.

    ``seed`` and ``tick`` are ``[B]`` int64; ``slot`` broadcasts against ``[B, K]`` (an int, or
    ``torch.arange(K)``); the result has the broadcast shape (``[B]`` or ``[B, K]``).
    """
    if isinstance(slot, torch.Tensor):
        if slot.dim() >= 1:
            seed, tick = seed.unsqueeze(-1), tick.unsqueeze(-1)
        # Adding a loaded zero makes the slots a value: compiled for CUDA, slots that come from an
        # arange are index arithmetic, which Triton did in int32, and ``slot * _KEY_SLOT`` failed
        # to compile (torch 2.11: "Scalar ... is out of range for type int32").
        slot = slot + (seed & 0)
    key = mix64(seed) + tick * _KEY_TICK + _int_term(slot, _KEY_SLOT) + _int_term(stream, _KEY_STREAM)
    return mix64(mix64(key))


def _int_term(value: torch.Tensor | int, key: int) -> torch.Tensor | int:
    """``value * key`` wrapped as int64 arithmetic wraps it: a Python int's product past 2^63
    would not convert to a tensor (streams and int slots from 2 on). In a compiled graph the
    product is the graph's own int64 arithmetic, which wraps by itself; ``_signed`` on a symbolic
    int would not trace."""
    if isinstance(value, int) and not torch.compiler.is_compiling():
        return _signed(value * key)
    return value * key


def uniform(seed: torch.Tensor, tick: torch.Tensor, slot: torch.Tensor | int, stream: int) -> torch.Tensor:
    """U[0, 1) as float64 (53 random bits), see :func:`hash_bits` for the shapes."""
    return _shift_right(hash_bits(seed, tick, slot, stream), 11).to(torch.float64) * (1.0 / (1 << 53))


def randint(
    seed: torch.Tensor, tick: torch.Tensor, slot: torch.Tensor | int, stream: int, high: int
) -> torch.Tensor:
    """Uniform integers in [0, high), see :func:`hash_bits` for the shapes."""
    return _shift_right(hash_bits(seed, tick, slot, stream), 1) % high


def derive_seeds(base_seed: int, count: int, offset: int = 0) -> torch.Tensor:
    """``count`` well-separated int64 seeds from one integer: seeds[i] depends only on (base, i)."""
    index = torch.arange(offset, offset + count, dtype=torch.int64)
    return mix64(mix64(torch.full_like(index, _signed(base_seed))) ^ index)
