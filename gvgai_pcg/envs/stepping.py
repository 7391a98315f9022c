"""``PlanRunner``: an env's ticks and observations, run as its ``StepPlan`` says.

One job: a step's tick, its observation and outputs, and the reset tick of freshly compiled envs,
compiled or eager (``gvgai_pcg.engine.step_plan``); the env keeps the episodes, levels and
outputs. Every choice was made when the plan was; what is left here is the plan's two paths.
"""

from __future__ import annotations

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.buffers import BufferPool
from gvgai_pcg.engine.compiled import MIN_COMPILED_BATCH, engine_tick
from gvgai_pcg.engine.outputs import episode_outputs
from gvgai_pcg.engine.rows import first_rows, select_rows
from gvgai_pcg.engine.step_plan import StepPlan
from gvgai_pcg.envs.shards import ShardedStepper
from gvgai_pcg.envs.states import entity_capacities, pad_entity_tables, slot_bucket
from gvgai_pcg.games.base import Game
from gvgai_pcg.games.render import render_pixels, render_tiles

Outputs = dict[str, torch.Tensor]


class PlanRunner:
    """Ticks and draws ``num_envs`` envs of ``game`` as ``plan`` says (``shards`` slices of the
    batch for an eager plan; whole-batch tiles drawn into ``buffers``)."""

    def __init__(
        self,
        game: Game,
        plan: StepPlan,
        obs: str,
        num_envs: int,
        max_steps: int,
        shards: int,
        buffers: BufferPool,
    ) -> None:
        self.game, self.plan, self.obs = game, plan, obs
        self.num_envs, self.max_steps, self.buffers = num_envs, max_steps, buffers
        self.compiled_tick = engine_tick(game) if plan.compiled else None
        self.sharded = ShardedStepper(shards)

    def step(
        self, state: TensorDict, action: torch.Tensor, steps: torch.Tensor
    ) -> tuple[torch.Tensor, Outputs]:
        """One step of ``state``: its observation and ``episode_outputs`` with the reward."""
        if self.plan.fused:
            fused = self.compiled_tick.tick_and_draw(state, action, steps, self.max_steps)
            if fused is not None:  # the tick, the tiles and the other outputs in one call
                return fused
        before = state.get("score").clone()  # a sharded step writes the new score into it
        observed = self.sharded(self._tick, state, action)
        return observed, episode_outputs(state, steps, self.max_steps, score_before=before)

    def reset_tick(
        self, fresh: TensorDict, observe: bool, running: TensorDict | None
    ) -> tuple[TensorDict, torch.Tensor | None]:
        """The reset tick (RULES.md §1.8) of ``fresh`` envs beside the ``running`` state (None
        before the first reset): ``fresh`` after it and, if ``observe``, their observations."""
        if self.plan.compiled_resets:
            return self._compiled_reset_tick(fresh, observe, running)
        nil = torch.zeros(len(fresh), dtype=torch.int64, device=fresh.device)
        observed = self.sharded(self._reset_tick if observe else self._reset_tick_only, fresh, nil)
        return fresh, observed if observe else None

    def render(self, state: TensorDict) -> torch.Tensor:
        """The observation of ``state``; whole-batch tiles are drawn into recycled buffers (the size
        of a partial reset varies)."""
        if self.obs == "pixels":
            return render_pixels(self.game, state)
        return render_tiles(self.game, state, self.buffers if len(state) == self.num_envs else None)

    def _tick(self, state: TensorDict, action: torch.Tensor) -> torch.Tensor:
        """One tick of ``state``, then its observation (the work of one shard)."""
        if self.compiled_tick is None:
            self.game.tick(state, action)
        else:
            self.compiled_tick.run(state, action, self.plan.large_graph)
        return self.render(state)

    def _reset_tick(self, state: TensorDict, nil: torch.Tensor) -> torch.Tensor:
        """The game's reset tick of fresh envs, then their observation (the work of one shard)."""
        self.game.reset_tick(state)
        return self.render(state)

    def _reset_tick_only(self, state: TensorDict, nil: torch.Tensor) -> torch.Tensor:
        """The reset tick and no observation (an empty ``[N, 0]``, for the stepper)."""
        self.game.reset_tick(state)
        return nil.new_empty(nil.shape[0], 0)

    def _compiled_reset_tick(
        self, fresh: TensorDict, observe: bool, running: TensorDict | None
    ) -> tuple[TensorDict, torch.Tensor | None]:
        """The reset tick of ``fresh`` envs run by the engine's compiled tick (and, where the steps
        are fused, drawn in the same call), which equals the game's reset tick (RULES.md §1.8,
        tested per game).

        Eagerly a partial reset's tick costs a whole tick's few hundred small ops, however few its
        envs: it was most of a step's time in Solarfox's training. So that the compiled graphs
        already made serve it, its entity tables are grown to the running state's widths (or
        their own power of two, if larger; empty slots change nothing), and a single env is
        ticked twice over (the compiler would specialise a batch of one, see
        ``MIN_COMPILED_BATCH``; every env is independent of the others)."""
        count, device = len(fresh), fresh.device
        widths = entity_capacities(running) if running is not None else {}
        widths = {
            key: max(slot_bucket(size), widths.get(key, 0)) for key, size in entity_capacities(fresh).items()
        }
        batch = pad_entity_tables(fresh, widths)
        if count < MIN_COMPILED_BATCH:
            batch = select_rows(batch, torch.zeros(MIN_COMPILED_BATCH, dtype=torch.int64, device=device))
        nil = torch.zeros(len(batch), dtype=torch.int64, device=device)
        fused = None
        # The steps' graph ticks and draws in one call where this env's steps do, whatever the
        # size of this batch (episodes prepared ahead come several hundred at a time): the tick
        # alone would be another graph to compile, seconds for a few rare calls. Steps of their
        # own: the step's graph takes distinct tensors (an aliased pair would be another graph).
        if self.plan.fused:
            fused = self.compiled_tick.tick_and_draw(batch, nil, torch.zeros_like(nil), self.max_steps)
        observed = fused[0] if fused is not None and observe else None
        if fused is None:  # not ticked in one call with the tiles (the tick has not run then)
            self.compiled_tick.run(batch, nil, self.plan.large_graph)
            observed = self.render(batch) if observe else None
        if count < MIN_COMPILED_BATCH:
            batch = first_rows(batch, count)
            observed = observed[:count] if observed is not None else None
        return batch, observed
