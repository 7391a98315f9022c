"""The tick the engine runs: a game's tick compiled into a few fused kernels where it can be
(and, for small batches, the tiles drawn the same way: ``CompiledRender``).

At the batches training uses (12-64 envs) an eager tick costs its ~250 small ops, not its work:
about 1-2 ms whatever the batch. ``torch.compile`` fuses a tick that traces as one graph
(``Game.compiles``) into a few loops over the envs. On the CPU those loops are kept scalar
(``cpp.simdlen = 0``): inductor's vectorised code runs 16-lane masked int64 vectors over entity
tables of a handful of slots and was 3-5x slower than eager at B = 1024-4096, where the scalar
code is 2-3x faster (docs/benchmarks.md, "The compiled tick").

Shapes are dynamic, so one compilation serves every batch size and level size (on several threads
large batches get a graph of their own: ``LARGE_BATCH_PER_THREAD``); a different entity-table width
can still recompile (the ordered stepBack loops over its slots), which is why
a running state grows its tables to a power of two (``gvgai_pcg.envs.states``). Compiling needs a
C++ compiler on the CPU (Triton on CUDA); where it fails the engine warns once and runs the
eager tick, which computes the same. ``GVGAI_PCG_COMPILE=0`` turns compiling off. What a tick
takes from the host (``Game.host_arguments``: whole-batch choices, one graph each, and tables) is
read before the graph runs; a choice whose graph inductor gets wrong (``Game.eager_when``) ticks
eagerly.
"""

from __future__ import annotations

import os
import threading
import warnings
from collections.abc import Callable

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.outputs import episode_outputs
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
# Inductor makes a loop parallel only where its size hint gives each thread at least
# ``cpp.min_chunk_size`` (512) iterations, and the hint is the size of the first trace: every
# later batch size reuses that graph. A tick first traced at 64 envs ran its loops over the envs
# on one thread at 4,096 too: Zelda, 2 threads, 1,831 us a tick at 4,096 and 592 at 1,024, against
# 1,071 and 414 for a graph first traced at 4,096. So from this many envs a thread the tick runs a
# graph of its own, first traced at such a batch (``CompiledTick.large_batch``).
LARGE_BATCH_PER_THREAD = 512
# Options of that graph: it has to differ from the small batches' graph in something inductor's
# on-disk cache hashes, since the cache's key leaves out size hints and would hand either graph's
# code to the other. A smaller minimum chunk changes no loop at the batches it runs.
LARGE_BATCH_OPTIONS = {**INDUCTOR_OPTIONS, "cpp.min_chunk_size": LARGE_BATCH_PER_THREAD // 2}

# What compiling raises (an error inside a compiled tick is not among them and propagates).
COMPILE_ERRORS = (torch._dynamo.exc.TorchDynamoException, torch._dynamo.exc.FailOnRecompileLimitHit)

Tick = Callable[[TensorDict, torch.Tensor], None]


def compiling_enabled() -> bool:
    """Whether the engine compiles ticks (``GVGAI_PCG_COMPILE=0`` says no)."""
    return os.environ.get(COMPILE_VARIABLE, "1").strip().lower() not in ("0", "false", "no", "off")


_THREAD = threading.local()


def _configure_this_thread() -> None:
    """Compiler settings for the ticks compiled in this thread (torch 2.13 keeps these settings per
    thread, and a sharded env ticks in a pool's threads)."""
    # Only ever raised: every entity-table width and shard offset a run meets compiles once.
    limit = torch._dynamo.config.recompile_limit
    torch._dynamo.config.recompile_limit = max(limit, RECOMPILE_LIMIT)
    # Duck shaping gives sizes that are equal when first traced one symbol. Inductor (torch 2.13)
    # then miscompiled Boulderdash's tick for a batch of 4 envs with 4 monster slots each: the
    # monsters moved differently from the eager tick (tests/engine/test_compiled.py). Every size
    # gets its own symbol instead, which only drops an assumption (and the recompiles it caused
    # when two tables tied at first trace later differed).
    torch.fx.experimental._config.use_duck_shape = False
    _THREAD.configured = True


def _configured_thread() -> None:
    """Configure this thread's compiler settings once (see ``_configure_this_thread``)."""
    if not getattr(_THREAD, "configured", False):
        _configure_this_thread()


def _failure_message(error: Exception) -> str:
    """The one line a warning gives of a compiler error."""
    return f"{type(error).__name__}: {str(error).strip().splitlines()[0][:300]}"


class CompiledTick:
    """``game.tick`` compiled on first use; on a device where compiling fails (no C++ compiler,
    an unsupported op) it says so and falls back to the eager tick there for good."""

    def __init__(self, game: Game) -> None:
        self.game = game
        self._compiled = torch.compile(
            type(game).tick, fullgraph=True, dynamic=True, options=INDUCTOR_OPTIONS
        )
        self._compiled_large = torch.compile(
            type(game).tick, fullgraph=True, dynamic=True, options=LARGE_BATCH_OPTIONS
        )
        # Why compiling failed, per device type: a device where it failed ticks eagerly from then
        # on; the others still compile (a CUDA compiler error leaves the CPU tick compiled).
        self.failures: dict[str, str] = {}
        self.failure_details: dict[str, str] = {}  # the compiler's whole message, for a bug report
        # The tick with its tiles render in one graph, and the device types where that failed.
        self._compiled_and_drawn = torch.compile(
            tick_and_draw, fullgraph=True, dynamic=True, options=INDUCTOR_OPTIONS
        )
        self.fused_failures: dict[str, str] = {}

    @property
    def failed(self) -> str | None:
        """Why compiling failed on some device (None where it never did)."""
        return next(iter(self.failures.values()), None)

    def large_batch(self, batch: int, device: torch.device | str = "cpu") -> bool:
        """Whether a batch of ``batch`` envs ticks through the graph for large batches (see
        ``LARGE_BATCH_PER_THREAD``); with one thread no loop is parallel and one graph serves all.
        The CPU only: CUDA's kernels are not split over threads this way (and not measured)."""
        threads = torch.get_num_threads()  # the cheap tests first: this runs at every compiled tick
        return (
            threads > 1
            and batch >= LARGE_BATCH_PER_THREAD * threads
            and self.game.parallel_graph
            and torch.device(device).type == "cpu"
        )

    def _host_arguments(self, state: TensorDict, action: torch.Tensor) -> tuple[dict | None, bool]:
        """The host arguments of the next tick of ``state`` (None where it is not worked out) and
        whether the tick may run compiled."""
        batch, largest = state.batch_size[0], self.game.max_compiled_batch
        device = action.device.type
        if not (
            device in self.game.compiled_devices
            and device not in self.failures
            and MIN_COMPILED_BATCH <= batch
            and (largest is None or batch <= largest)
        ):
            return None, False
        _configured_thread()
        arguments = self.game.host_arguments(state)
        return arguments, not any(arguments[name] for name in self.game.eager_when)

    def _compile_failed(self, failures: dict[str, str], what: str, device: str, error: Exception) -> None:
        message = _failure_message(error)
        failures[device] = message
        if failures is self.failures:
            self.failure_details[device] = str(error)
        warnings.warn(
            f"compiling {self.game.name}'s {what} for {device} failed ({message}); the engine "
            f"runs it eagerly there, which computes the same, several times slower at small "
            f"batches (set {COMPILE_VARIABLE}=0 to skip the attempt)",
            RuntimeWarning,
            stacklevel=3,
        )

    def __call__(self, state: TensorDict, action: torch.Tensor) -> None:
        arguments, compiled = self._host_arguments(state, action)
        if arguments is None:
            self.game.tick(state, action)
        elif not compiled:
            self.game.tick(state, action, **arguments)
        else:
            compiled_tick = (
                self._compiled_large if self.large_batch(len(action), action.device) else self._compiled
            )
            try:
                compiled_tick(self.game, state, action, **arguments)
            except COMPILE_ERRORS as error:  # raised while compiling, before the tick ran
                self._compile_failed(self.failures, "tick", action.device.type, error)
                self.game.tick(state, action, **arguments)

    def tick_and_draw(
        self, state: TensorDict, action: torch.Tensor, steps: torch.Tensor, max_steps: int
    ) -> tuple[torch.Tensor, dict[str, torch.Tensor]] | None:
        """The tick, then the tiles it leaves (``render_tiles_traced``) and the step's other
        outputs (``episode_outputs`` after ``steps`` steps of ``max_steps``, and the ``reward``,
        ``[B, 1]`` float32), as one compiled call; None where that call does not apply or failed
        to compile, and the caller ticks and draws apart (the tick has not run then). A tick and a
        compiled render called in turn each pay a compiled call's fixed cost and run between other
        work that evicts their code from the caches: at 64 Zelda envs the two took 366 us in an
        env's step and this one 224 us; the outputs, eagerly a dozen small ops, add almost nothing
        to it."""
        device = action.device.type
        if device in self.fused_failures:
            return None
        arguments, compiled = self._host_arguments(state, action)
        if not compiled:
            return None
        try:
            return self._compiled_and_drawn(self.game, state, action, steps, max_steps, **arguments)
        except COMPILE_ERRORS as error:  # raised while compiling, before the tick ran
            self._compile_failed(self.fused_failures, "tick and tiles render", device, error)
            return None


def tick_and_draw(
    game: Game,
    state: TensorDict,
    action: torch.Tensor,
    steps: torch.Tensor,
    max_steps: int,
    **arguments: object,
) -> tuple[torch.Tensor, dict[str, torch.Tensor]]:
    """One tick of ``state``, then its tiles and the step's other outputs: what
    ``CompiledTick.tick_and_draw`` compiles."""
    from gvgai_pcg.games.render import render_tiles_traced

    before = state.get("score").clone()
    type(game).tick(game, state, action, **arguments)
    return render_tiles_traced(game, state), episode_outputs(state, steps, max_steps, score_before=before)


class CompiledRender:
    """Whole-batch tiles of a small batch drawn by ``render_tiles_traced`` compiled. Eager, a
    render costs its ~50 small ops (about 0.22-0.33 ms a batch whatever the game); compiled it is
    a few loops, 2.4x as fast for Zelda at 12 envs and 2.2x at 64. Its scalar loops cost more per
    byte than the eager copies, though, so it draws batches of at most ``MAX_BYTES`` tile bytes:
    on one thread (2026-11-26, compiled / eager) Zelda 2.4x at 12.6k bytes, 2.2x at 67k and 1.7x
    at 270k; Boulderdash 1.9x at 37k, 1.3x at 195k and 0.7x at 779k; Solarfox 1.4x at 70k and 0.9x
    at 282k; Frogs 1.4x at 41k and 0.9x at 217k. The CPU only: it has not been checked on CUDA.
    """

    MAX_BYTES = 200_000
    # Drawn in the same call as the tick (CompiledTick.tick_and_draw), which saves a compiled
    # call's fixed cost, batches of up to about twice as many bytes gain. On one thread
    # (2026-11-26, tick and tiles in one call / compiled tick then eager render): Frogs 0.85x at
    # 217k bytes and 1.04x at 434k; Boulderdash 0.83x at 389k and 0.99x at 779k; Solarfox 0.89x
    # at 282k and 1.07x at 563k; Zelda 0.61x at 270k and 0.72x at 539k.
    FUSED_MAX_BYTES = 400_000
    DEVICES = ("cpu",)

    def __init__(self) -> None:
        from gvgai_pcg.games.render import render_tiles_traced

        self._compiled = torch.compile(
            render_tiles_traced, fullgraph=True, dynamic=True, options=INDUCTOR_OPTIONS
        )
        # Why compiling failed, per game class and device type, each then drawn eagerly.
        self.failures: dict[tuple[type, str], str] = {}

    def applies(self, game: Game, batch: int, device: torch.device, max_bytes: int | None = None) -> bool:
        """Whether a batch of ``batch`` envs of ``game`` on ``device`` is drawn compiled (with tiles
        of at most ``max_bytes``, by default ``MAX_BYTES``)."""
        if not (
            compiling_enabled()
            and device.type in self.DEVICES
            and (type(game), device.type) not in self.failures
            and MIN_COMPILED_BATCH <= batch
        ):
            return False
        grid = game.level_format
        limit = self.MAX_BYTES if max_bytes is None else max_bytes
        return batch * len(game.tile_types) * grid.height * grid.width <= limit

    def __call__(self, game: Game, state: TensorDict) -> torch.Tensor | None:
        """The tiles, or None where compiling failed (the caller draws them eagerly)."""
        _configured_thread()
        try:
            return self._compiled(game, state)
        except COMPILE_ERRORS as error:
            device = state.device.type if state.device is not None else "cpu"
            message = _failure_message(error)
            self.failures[(type(game), device)] = message
            warnings.warn(
                f"compiling {game.name}'s tiles render for {device} failed ({message}); they are "
                f"drawn eagerly there, which draws the same",
                RuntimeWarning,
                stacklevel=2,
            )
            return None


COMPILED_RENDER = CompiledRender()

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
