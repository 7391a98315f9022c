"""The tick the engine runs: a game's tick compiled into a few fused kernels where it can be
(and, for small batches, the tiles drawn in the same call: ``CompiledTick.tick_and_draw``). Which
env runs it is decided once, by ``gvgai_pcg.engine.step_plan``.

At the batches training uses (12-64 envs) an eager tick costs its ~250 small ops, not its work:
about 1-2 ms whatever the batch. ``torch.compile`` fuses a tick that traces as one graph
(``StepFacts.compiles``) into a few loops over the envs. On the CPU those loops are kept scalar
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
read before the graph runs; a choice whose graph inductor gets wrong (``StepFacts.eager_when``)
ticks eagerly.
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
from gvgai_pcg.games.render import render_tiles_traced
from gvgai_pcg.games.spec import StepFacts

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
# graph of its own, first traced at such a batch (``large_batch``).
LARGE_BATCH_PER_THREAD = 512
# Options of that graph: it has to differ from the small batches' graph in something inductor's
# on-disk cache hashes, since the cache's key leaves out size hints and would hand either graph's
# code to the other. A smaller minimum chunk changes no loop at the batches it runs.
LARGE_BATCH_OPTIONS = {**INDUCTOR_OPTIONS, "cpp.min_chunk_size": LARGE_BATCH_PER_THREAD // 2}
# The most tile bytes (envs x tile types x cells) whose tiles are drawn compiled, in the tick's call
# (``CompiledTick.tick_and_draw``); a larger batch ticks compiled and draws eagerly. Eager, a
# render costs its ~50 small ops (about 0.22-0.33 ms a batch whatever the game); compiled, its
# scalar loops cost more per byte than the eager copies. On one thread (tick and tiles in one call
# / compiled tick then eager render; docs/history/benchmarks-notebook.md, "The small-batch step"):
# Frogs 0.85x at 217k bytes and 1.04x at 434k; Boulderdash 0.83x at 389k and 0.99x at 779k;
# Solarfox 0.89x at 282k and 1.07x at 563k; Zelda 0.61x at 270k and 0.72x at 539k. The CPU
# only: not checked on CUDA.
FUSED_MAX_BYTES = 400_000

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


def configure_compiler_thread() -> None:
    """Configure this thread's compiler settings once (see ``_configure_this_thread``)."""
    if not getattr(_THREAD, "configured", False):
        _configure_this_thread()


def compiled_batch(facts: StepFacts, batch: int, device: torch.device | str) -> bool:
    """Whether a batch of ``batch`` envs on ``device`` of a game with ``facts`` ticks compiled."""
    largest = facts.max_compiled_batch
    return (
        facts.compiles
        and torch.device(device).type in facts.compiled_devices
        and MIN_COMPILED_BATCH <= batch
        and (largest is None or batch <= largest)
    )


def large_batch(facts: StepFacts, batch: int, device: torch.device | str, threads: int) -> bool:
    """Whether a batch of ``batch`` envs ticks through the graph for large batches (see
    ``LARGE_BATCH_PER_THREAD``) on ``threads`` torch threads; with one thread no loop is parallel
    and one graph serves all. The CPU only: CUDA's kernels are not split over threads this way."""
    return (
        threads > 1
        and batch >= LARGE_BATCH_PER_THREAD * threads
        and facts.parallel_graph
        and torch.device(device).type == "cpu"
    )


def _failure_message(error: Exception) -> str:
    """The one line a warning gives of a compiler error."""
    return f"{type(error).__name__}: {str(error).strip().splitlines()[0][:300]}"


class CompiledTick:
    """``game.tick`` compiled on first use; on a device where compiling fails (no C++ compiler,
    an unsupported op) it says so and falls back to the eager tick there for good."""

    def __init__(self, game: Game) -> None:
        self.game, self.facts = game, game.step_facts
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

    def _arguments(self, state: TensorDict, device: str) -> tuple[dict, bool]:
        """The host arguments of the next tick of ``state`` and whether it may run compiled (not
        where compiling failed on ``device``, nor where an ``eager_when`` argument holds)."""
        configure_compiler_thread()
        arguments = self.game.host_arguments(state)
        eager = device in self.failures or any(arguments[name] for name in self.facts.eager_when)
        return arguments, not eager

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

    def run(self, state: TensorDict, action: torch.Tensor, large: bool = False) -> None:
        """The tick, compiled, for a caller that has chosen to run it compiled (an env's
        ``StepPlan``): ``large`` picks the graph for large batches. Only the data decides here: an
        ``eager_when`` argument, or a device where compiling failed, ticks eagerly."""
        arguments, compiled = self._arguments(state, action.device.type)
        if not compiled:
            self.game.tick(state, action, **arguments)
            return
        try:
            (self._compiled_large if large else self._compiled)(self.game, state, action, **arguments)
        except COMPILE_ERRORS as error:  # raised while compiling, before the tick ran
            self._compile_failed(self.failures, "tick", action.device.type, error)
            self.game.tick(state, action, **arguments)

    def __call__(self, state: TensorDict, action: torch.Tensor) -> None:
        """The tick of any batch (benchmarks, the golden replays): compiled where an env of this
        batch and device would tick compiled (``compiled_batch``), with the threads set now."""
        batch, device = len(action), action.device
        if not compiled_batch(self.facts, batch, device):
            self.game.tick(state, action)
            return
        self.run(state, action, large_batch(self.facts, batch, device, torch.get_num_threads()))

    def tick_and_draw(
        self, state: TensorDict, action: torch.Tensor, steps: torch.Tensor, max_steps: int
    ) -> tuple[torch.Tensor, dict[str, torch.Tensor]] | None:
        """The tick, then the tiles it leaves (``render_tiles_traced``) and the step's other
        outputs (``episode_outputs`` after ``steps`` steps of ``max_steps``, and the ``reward``,
        ``[B, 1]`` float32), as one compiled call, for a caller whose plan fuses them; None where
        the data asks for the eager tick or that call failed to compile, and the caller ticks and
        draws apart (the tick has not run then). A tick and a compiled render called in turn each
        pay a compiled call's fixed cost and run between other work that evicts their code from
        the caches: at 64 Zelda envs the two took 366 us in an env's step and this one 224 us; the
        outputs, eagerly a dozen small ops, add almost nothing to it."""
        device = action.device.type
        if device in self.fused_failures:
            return None
        arguments, compiled = self._arguments(state, device)
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
    before = state.get("score").clone()
    type(game).tick(game, state, action, **arguments)
    return render_tiles_traced(game, state), episode_outputs(state, steps, max_steps, score_before=before)


_TICKS: dict[type, Tick] = {}


def engine_tick(game: Game) -> Tick:
    """The tick the engine runs for ``game``: compiled where the game traces as one graph and
    compiling is on, else ``game.tick`` itself. One per game class, shared (compiling is slow)."""
    if not (game.step_facts.compiles and compiling_enabled()):
        return game.tick
    tick = _TICKS.get(type(game))
    if tick is None:
        tick = _TICKS[type(game)] = CompiledTick(game)
    return tick
