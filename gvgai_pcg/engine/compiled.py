"""The tick the engine runs: a game's tick compiled into a few fused kernels where it can be.

At the batches training uses (12-64 envs) an eager tick costs its ~250 small ops, not its work:
about 1-2 ms whatever the batch. ``torch.compile`` fuses a tick that traces as one graph
(``Game.compiles``) into a few loops over the envs. On the CPU those loops are kept scalar
(``cpp.simdlen = 0``): inductor's vectorised code runs 16-lane masked int64 vectors over entity
tables of a handful of slots and was 3-5x slower than eager at B = 1024-4096, where the scalar
code is 2-3x faster (docs/benchmarks.md, "The compiled tick").

Shapes are dynamic, so one compilation serves every batch size and level size; a different
entity-table width can still recompile (the ordered stepBack loops over its slots), which is why
a running state grows its tables to a power of two (``gvgai_pcg.envs.states``). Compiling needs a
C++ compiler on the CPU (Triton on CUDA); where it fails the engine warns once and runs the
eager tick, which computes the same. ``GVGAI_PCG_COMPILE=0`` turns compiling off.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable

import torch
from tensordict import TensorDict

from gvgai_pcg.games.base import Game

COMPILE_VARIABLE = "GVGAI_PCG_COMPILE"
# Scalar C++ loops on the CPU (see the module docstring); no effect on CUDA.
INDUCTOR_OPTIONS = {"cpp.simdlen": 0}
# A single env ticks eagerly: inductor (torch 2.13) specialises a batch of one and miscompiled
# Zelda's tick for one such level (an out-of-bounds index in the generated kernel, golden trace
# zelda_sword_kill), which the same level batched three times ticks exactly.
MIN_COMPILED_BATCH = 2
# Every entity-table width a batch can reach recompiles once; these are few (powers of two).
RECOMPILE_LIMIT = 32

# What compiling raises (an error inside a compiled tick is not among them and propagates).
COMPILE_ERRORS = (torch._dynamo.exc.TorchDynamoException, torch._dynamo.exc.FailOnRecompileLimitHit)

Tick = Callable[[TensorDict, torch.Tensor], None]


def compiling_enabled() -> bool:
    """Whether the engine compiles ticks (``GVGAI_PCG_COMPILE=0`` says no)."""
    return os.environ.get(COMPILE_VARIABLE, "1").strip().lower() not in ("0", "false", "no", "off")


class CompiledTick:
    """``game.tick`` compiled on first use; falls back to the eager tick, once and for good, if
    compiling fails (no C++ compiler, an unsupported op), after saying so."""

    def __init__(self, game: Game) -> None:
        self.game = game
        self._compiled = torch.compile(
            type(game).tick, fullgraph=True, dynamic=True, options=INDUCTOR_OPTIONS
        )
        self.failed: str | None = None
        # only ever raised; patching it per call would cost more than a small tick
        limit = torch._dynamo.config.recompile_limit
        torch._dynamo.config.recompile_limit = max(limit, RECOMPILE_LIMIT)

    def __call__(self, state: TensorDict, action: torch.Tensor) -> None:
        if self.failed is None and state.batch_size[0] >= MIN_COMPILED_BATCH:
            try:
                return self._compiled(self.game, state, action)
            except COMPILE_ERRORS as error:  # raised while compiling, before the tick ran
                self.failed = f"{type(error).__name__}: {str(error).strip().splitlines()[0][:300]}"
                warnings.warn(
                    f"compiling {self.game.name}'s tick failed ({self.failed}); the engine runs it "
                    f"eagerly, which computes the same, several times slower at small batches "
                    f"(set {COMPILE_VARIABLE}=0 to skip the attempt)",
                    RuntimeWarning,
                    stacklevel=2,
                )
        self.game.tick(state, action)


_TICKS: dict[type, Tick] = {}


def engine_tick(game: Game) -> Tick:
    """The tick the engine runs for ``game``: compiled where the game traces as one graph and
    compiling is on, else ``game.tick`` itself. One per game class, shared (compiling is slow)."""
    if not (game.compiles and compiling_enabled()):
        return game.tick
    tick = _TICKS.get(type(game))
    if tick is None:
        tick = _TICKS[type(game)] = CompiledTick(game)
    return tick
