"""How an env steps, chosen once when the env is made: ``StepPlan``.

An env steps one of two ways. **Compiled**: the game's tick run by the engine's ``CompiledTick``
(for the tiles of a small batch, the tick, the tiles and the step's other outputs in one compiled
call), its resets ticked by the same graph. **Eager**, the reference: the game's own tick, reset
tick and render. ``choose_step_plan`` decides between them, and among the compiled variants, from
the game's ``StepFacts``, the device, the batch, the observation kind and the torch threads; the
env keeps that plan for its lifetime and never decides again while it steps (tested). What is
left to a tick is data, not a choice of path: a game's host arguments, and its miscompile
opt-outs (``StepFacts.eager_when``).

One guard stays below the plan: where compiling itself fails (no C++ compiler), ``CompiledTick``
warns once and ticks eagerly on that device, which computes the same.
"""

from __future__ import annotations

from dataclasses import dataclass

import torch

from gvgai_pcg.engine.compiled import (
    FUSED_MAX_BYTES,
    MIN_COMPILED_BATCH,
    compiled_batch,
    compiling_enabled,
    large_batch,
)
from gvgai_pcg.games.base import Game

# Compiling the tick pays back only past this many batched steps of a job (an evaluation, a
# training run). The protocol on one Zelda run (210 envs, 2,000 steps, one thread):
# compiling cost about 7.7 s of CPU with a warm inductor cache (about 30 s cold) and saved 0.85 ms
# a batched step, so it breaks even near 9,000 steps warm. A 20k-frame Frogs training job (64
# envs, 312 batched steps) took 24.0 s compiled with a warm cache against 7.6 s eagerly
# (docs/history/benchmarks-notebook.md, "Evaluation: the protocol on one run"; docs/training.md).
COMPILE_PAYS_BACK_STEPS = 10_000


def compile_pays_back(batched_steps: int, device: torch.device | str) -> bool:
    """Whether a job of ``batched_steps`` batched steps should tick compiled (the CPU's
    measurement, ``COMPILE_PAYS_BACK_STEPS``; another device keeps the engine's own choice)."""
    return torch.device(device).type != "cpu" or batched_steps >= COMPILE_PAYS_BACK_STEPS


@dataclass(frozen=True)
class StepPlan:
    """How an env steps (see the module docstring).

    Args:
        compiled: the tick runs compiled (``CompiledTick``); else the game's eager tick.
        fused: a step's tick, tiles and other outputs run as one compiled call
            (``CompiledTick.tick_and_draw``); else the tick, then an eager render.
        large_graph: the tick runs the graph for large batches on several threads
            (``LARGE_BATCH_PER_THREAD``).
        compiled_resets: resets tick through the compiled tick (else the game's ``reset_tick``).
        reason: why the env steps this way, in a few words.
    """

    compiled: bool
    fused: bool = False
    large_graph: bool = False
    compiled_resets: bool = False
    reason: str = ""

    def __repr__(self) -> str:
        if not self.compiled:
            return f"StepPlan(eager: {self.reason})"
        parts = ["tick+tiles fused" if self.fused else "tick"]
        parts += ["large-batch graph"] * self.large_graph + ["resets compiled"] * self.compiled_resets
        return f"StepPlan(compiled: {', '.join(parts)}; {self.reason})"


def eager_plan(reason: str) -> StepPlan:
    """The reference plan: the game's own tick, reset tick and render."""
    return StepPlan(compiled=False, reason=reason)


def choose_step_plan(
    game: Game,
    num_envs: int,
    device: torch.device,
    obs: str = "tiles",
    shards: int = 1,
    compile_tick: bool = True,
) -> StepPlan:
    """The plan of an env of ``num_envs`` envs of ``game`` on ``device`` observing ``obs``; the
    torch threads are read now (set them before making the env)."""
    facts = game.step_facts
    if not compile_tick:
        return eager_plan("compile_tick=False")
    if not compiling_enabled():
        return eager_plan("GVGAI_PCG_COMPILE=0")
    if not facts.compiles:
        return eager_plan(f"{game.name}'s tick does not trace as one graph")
    # On a shard's views of the state, inductor (torch 2.13) miscompiled Boulderdash's tick (its
    # monsters' moves came out differently from run to run), so a sharded env ticks eagerly.
    if shards > 1:
        return eager_plan(f"{shards} shards")
    if not compiled_batch(facts, num_envs, device):
        if device.type not in facts.compiled_devices:
            return eager_plan(f"{game.name} is not compiled on {device.type}")
        if num_envs < MIN_COMPILED_BATCH:
            return eager_plan("a single env")
        return eager_plan(f"{num_envs} envs, above {game.name}'s {facts.max_compiled_batch}")
    grid = game.level_format
    tile_bytes = num_envs * len(game.tile_types) * grid.height * grid.width
    # Tiles drawn compiled in the tick's call pay where they are few bytes, on the CPU (measured in
    # gvgai_pcg.engine.compiled: FUSED_MAX_BYTES); not checked on CUDA.
    fused = obs == "tiles" and device.type == "cpu" and tile_bytes <= FUSED_MAX_BYTES
    large = large_batch(facts, num_envs, device, torch.get_num_threads())
    # A game with a lighter reset tick of its own keeps it: Frogs' does a third of a tick's work,
    # and ticking its resets compiled gained nothing at 12 and 64 envs and lost 5 % at 1,024 (one
    # thread, generated and human levels).
    resets = type(game).reset_tick is Game.reset_tick
    return StepPlan(True, fused, large, resets, f"{num_envs} envs on {device.type}")
