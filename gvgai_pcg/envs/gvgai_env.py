"""``GVGAIEnv``: a natively batched TorchRL environment over one game.

All ``num_envs`` environments live in one tensor state and advance in one ``game.tick``. The
env keeps the Gym's semantics (RULES.md §1.8): reset runs tick 0 with NIL, a step is one tick,
the reward is the score delta, and a step limit truncates. Partial resets (the ``"_reset"``
mask) start a new episode only in the masked envs, each with the next level from its level
source; for sources that know their levels in advance, those episodes are prepared in bulk ahead
of time (``gvgai_pcg.envs.prepared_resets``), with the same result.
"""

from __future__ import annotations

from collections.abc import Sequence
from os import PathLike

import numpy as np
import torch
from tensordict import TensorDict, TensorDictBase

from gvgai_pcg._private_apis import CompleteStepHook, unchecked_tensordict
from gvgai_pcg.engine.buffers import BufferPool
from gvgai_pcg.engine.outputs import episode_outputs
from gvgai_pcg.engine.rows import copy_tensor_rows_, select_rows
from gvgai_pcg.engine.step_plan import StepPlan, choose_step_plan
from gvgai_pcg.envs.inputs import (
    ActionCheck,
    checked_count,
    checked_device,
    checked_difficulty,
    checked_observation_kind,
    checked_seeds,
)
from gvgai_pcg.envs.level_bank import CompiledLevelBank
from gvgai_pcg.envs.level_sources import LevelSource, as_level_source
from gvgai_pcg.envs.prepared_resets import PreparedResets
from gvgai_pcg.envs.reset_rows import RowResetEnv
from gvgai_pcg.envs.specs import env_specs
from gvgai_pcg.envs.states import bucket_entity_tables, merge_states
from gvgai_pcg.envs.stepping import PlanRunner
from gvgai_pcg.games import get_game
from gvgai_pcg.games.render import ascii_frame, render_pixels
from gvgai_pcg.games.rng import derive_seeds, mix64
from gvgai_pcg.levels import Level

# Distinct recurring levels whose compiled state an env keeps (started, where tick 0 is seed-free).
COMPILED_LEVEL_CACHE = 64


class GVGAIEnv(CompleteStepHook, RowResetEnv):
    """``num_envs`` copies of ``game`` stepped together (batch size ``[num_envs]``).

    Actions: the ``"action"`` entry of a step holds one action per env, either as an index
    (``[B]`` or ``[B, 1]``, any integer dtype; the ``action_spec``, ``Categorical``, gives int64
    ``[B]``) or one-hot (``[B, A]``, any dtype, exactly one 1 per row), A being
    ``game.num_actions``; indices lie in ``0 .. A - 1`` (``game.actions`` names them). Anything
    else is refused with a ``ValueError`` that names the actions and their envs (see
    ``check_actions``).

    Observations: the observation is uint8 and its spec an ``Unbounded`` uint8 (tiles hold 0/1,
    pixels any value), which TorchRL's transforms rewrite: cast it (``DTypeCastTransform``) before
    ``ObservationNorm`` or ``VecNorm``. ``difficulty`` is float64, as the generators take it
    (``DoubleToFloat`` casts it for a model).

    Args:
        game: a registered game name (``zelda``, ``solarfox``, ``frogs``, ``boulderdash``).
        num_envs: the batch size B.
        levels: ``"human"`` (the five human levels, uniformly), a human level's name
            (``"zelda_lvl3"``), a level file, a folder of level files, a ``Level``, a list of these
            (one drawn uniformly each episode) or a ``LevelSource``.
        obs: ``"tiles"`` (``[C, H, W]`` uint8, one channel per sprite type) or ``"pixels"``
            (``[3, 10H, 10W]`` uint8 RGB).
        max_steps: the step limit that truncates an episode (the Gym's TimeLimit, 2000).
        device: where the state and every output tensor live (one present on this machine).
        seed: an int (per-env seeds are derived from it) or one seed per env. Env i's episode k
            uses the seed ``mix(env_seed[i], k)``, whatever else shares the batch.
        shards: on a CPU shared with other work, a step (and a reset's reset tick) can tick and
            render this many slices of the batch on as many threads, each with one torch thread
            (see ``gvgai_pcg.envs.shards``); the default, 1, uses torch's own intra-op threads,
            the faster choice on a quiet machine. The results do not depend on it. A sharded
            env ticks eagerly (gvgai_pcg.engine.step_plan).
        difficulty: the difficulty (in [0, 1]) of generated levels until a reset asks for another.
        check_actions: how action indices are range-checked. ``None`` (the default): on every
            step where the actions are on the CPU (no device sync), and without waiting on an
            accelerator where they are on one (a bad action stops the process there with a
            device-side assertion); ``True``: a ``ValueError`` wherever they are (on an
            accelerator, a host sync each step); ``False``: no range check (the shape and dtype
            are still checked). See ``gvgai_pcg.envs.inputs.ActionCheck``.
        compile_tick: ``False`` ticks and draws eagerly whatever ``GVGAI_PCG_COMPILE`` says, for a job
            too short to pay back compiling (``gvgai_pcg.evaluation.runner``). Same results. (Not
            ``compile``: TorchRL's env constructor takes that one for itself.)
    """

    batch_locked = True
    complete_reset_outputs = True  # _reset_output has every done entry (envs/reset_rows.py)

    def __init__(
        self,
        game: str,
        num_envs: int = 1,
        levels: LevelSource | Level | Sequence[Level | str | PathLike] | str | PathLike = "human",
        obs: str = "tiles",
        max_steps: int = 2000,
        device: torch.device | str = "cpu",
        seed: int | Sequence[int] = 0,
        difficulty: float = 0.0,
        shards: int = 1,
        check_actions: bool | None = None,
        compile_tick: bool = True,
    ) -> None:
        obs = checked_observation_kind(obs)
        num_envs, max_steps = checked_count("num_envs", num_envs), checked_count("max_steps", max_steps)
        shards, difficulty = checked_count("shards", shards), checked_difficulty(difficulty)
        device = checked_device(device)
        super().__init__(device=device, batch_size=torch.Size([num_envs]))
        self.game = get_game(game)
        self.buffers = BufferPool(keep=8)  # large whole-batch outputs, reused once released
        # How this env steps, decided here once (gvgai_pcg.engine.step_plan).
        plan = choose_step_plan(self.game, num_envs, self.device, obs, shards, compile_tick)
        self._runner = PlanRunner(self.game, plan, obs, num_envs, max_steps, shards, self.buffers)
        self.level_source = as_level_source(game, levels)
        self.obs_kind, self.max_steps, self.num_envs = obs, max_steps, num_envs
        # A compiled tick meets fewer table widths where they are rounded up (envs/states.py);
        # read once here, as every reset asks.
        self._round_up = self.game.step_facts.compiles
        fmt = self.game.level_format
        self.grid_height, self.grid_width = fmt.height, fmt.width
        self._env_seeds = checked_seeds(seed, num_envs)
        self._episodes = torch.zeros(num_envs, dtype=torch.int64)
        self._state: TensorDict | None = None
        self._own_entries: dict[str, torch.Tensor] | None = None  # difficulty and level entries
        self._observed: torch.Tensor | None = None  # the observation of the last output
        self._steps = torch.zeros(num_envs, dtype=torch.int64, device=self.device)
        self._difficulty = torch.full((num_envs,), difficulty, dtype=torch.float64, device=self.device)
        self._levels: list[Level | None] = [None] * num_envs
        # A step already run by the caller (``run_step_ahead``), output by the next ``_step``.
        self._step_ahead: tuple[torch.Tensor, torch.Tensor, dict[str, torch.Tensor]] | None = None
        # Where tick 0 draws nothing, recurring levels are banked started (envs/level_bank.py).
        start = self._start_levels if self.game.seed_free_reset_tick else None
        self._bank = CompiledLevelBank(
            self.game,
            self.grid_height,
            self.grid_width,
            self.device,
            COMPILED_LEVEL_CACHE,
            start,
            replayed=self.level_source.replayed_levels,
        )
        self._level_seeds = torch.full((num_envs,), -1, dtype=torch.int64)
        # The d each env's level was made at: the env's difficulty, or the source's own (DR).
        self._level_difficulties = torch.full((num_envs,), difficulty, dtype=torch.float64)
        for name, spec in env_specs(self.game, obs, num_envs, self.device).items():
            setattr(self, name, spec)
        self._check_action = ActionCheck(num_envs, tuple(self.game.actions), self.device, check_actions)
        # Sources whose next levels are known in advance get their partial resets prepared in bulk.
        observation_bytes = self.observation_spec[obs].shape.numel()  # uint8
        self._prepared_resets = PreparedResets.for_source(
            self.level_source, num_envs, observation_bytes, round_up=self._round_up
        )

    @property
    def step_plan(self) -> StepPlan:
        """How this env steps, chosen when it was made (``gvgai_pcg.engine.step_plan``)."""
        return self._runner.plan

    @property
    def env_seeds(self) -> torch.Tensor:
        """``[B]`` int64: the per-env seeds (pass one of them as ``seed=[s]`` to replay an env alone)."""
        return self._env_seeds.clone()

    @property
    def state(self) -> TensorDict:
        """The batched game state (see ``gvgai_pcg.games.base``); read it, do not keep it."""
        if self._state is None:
            raise RuntimeError("the env has not been reset yet")
        return self._state

    @property
    def current_levels(self) -> list[Level | None]:
        """The level each env is playing (as given by its source, before padding)."""
        return list(self._levels)

    # --- reset and step ---
    def _reset(self, tensordict: TensorDictBase | None = None, **kwargs) -> TensorDict:
        self._complete_entries = self._own_entries = None
        mask = None
        if tensordict is not None and "_reset" in tensordict.keys():
            mask = tensordict.get("_reset").reshape(self.num_envs).to(self.device)
        reset_all = self._state is None or mask is None
        index = torch.arange(self.num_envs) if reset_all else mask.nonzero().flatten().cpu()
        if tensordict is not None and "difficulty" in tensordict.keys():
            requested = tensordict.get("difficulty").reshape(self.num_envs).to(self.device, torch.float64)
            if reset_all:
                self._difficulty = requested.clone()  # not the caller's tensor
            else:
                self._difficulty = torch.where(mask, requested, self._difficulty)
        if reset_all:
            mask = torch.ones(self.num_envs, dtype=torch.bool, device=self.device)
        observed = self._observed
        if len(index) == self.num_envs:
            observed = self._start_episodes(index)
        elif len(index):
            # A partial reset renders only the fresh envs; the others keep the observation of
            # the last output (their state has not changed since), copied so that it stays as the
            # caller holds it.
            fresh = self._start_episodes(index)
            observed = copy_tensor_rows_(self.buffers.clone(observed), index.to(self.device), fresh)
        out = self._reset_output(self.state, observed, restarted=mask)
        if not reset_all:
            # Every row holds the running values, so the merge may take these entries whole.
            self._complete_entries = dict(out.items())
        return out

    def _start_episodes(self, index: torch.Tensor) -> torch.Tensor:
        """Start a new episode in envs ``index`` (CPU, sorted); returns their observations after
        the reset tick."""
        partial = self._state is not None and len(index) < self.num_envs
        rows = index.to(self.device)
        taken = None
        if self._prepared_resets is not None:
            taken = self._prepared_resets.take(
                self._state, index, self._episodes, self._difficulty, self._prepare
            )
        if taken is not None:
            self._state, levels, observed = taken
            if observed is None:
                observed = self._runner.render(select_rows(self._state, rows))
        else:
            fresh, levels, observed = self._prepare(index, observe=True)
            if not partial:
                self._state = bucket_entity_tables(fresh) if self._round_up else fresh
            else:
                self._state = merge_states(self._state, fresh, rows, round_up=self._round_up)
        self._episodes[index] += 1
        for i, level in zip(index.tolist(), levels, strict=True):
            self._levels[i] = level
        self._steps[rows] = 0
        self._level_seeds[index] = torch.tensor([lv.seed if lv.seed is not None else -1 for lv in levels])
        self._level_difficulties[index] = self._level_difficulties_of(index, self._episodes[index] - 1)
        return observed

    def _level_difficulties_of(self, index: torch.Tensor, episodes: torch.Tensor) -> torch.Tensor:
        """The d at which episodes ``episodes`` of envs ``index`` made their levels: the env's
        difficulty, unless the source draws its own (``level_difficulties``, as DR does)."""
        difficulties = self._difficulty[index.to(self.device)].cpu()
        drawn = self.level_source.level_difficulties
        if drawn is None:
            return difficulties
        return drawn(index, mix64(self._env_seeds[index] ^ mix64(episodes)), difficulties)

    def _prepare(
        self, index: torch.Tensor, observe: bool, episodes: torch.Tensor | None = None
    ) -> tuple[TensorDict, list[Level], torch.Tensor | None]:
        """Episodes ``episodes`` (by default, the next) of envs ``index`` (CPU): their states after
        the reset tick, their levels and, if ``observe``, their observations. Depends only on each
        env's seed, episode number and difficulty (and its level source)."""
        episodes = self._episodes[index] if episodes is None else episodes
        episode_seeds = mix64(self._env_seeds[index] ^ mix64(episodes))
        difficulties = self._difficulty[index.to(self.device)].cpu()
        levels = self.level_source.next_levels(index, episode_seeds, difficulties)
        recur = self.level_source.levels_recur
        fresh, started, observed = self._bank.fresh_states(levels, episode_seeds, recur)
        if not started:  # compiled: the reset tick runs here
            fresh, observed = self._runner.reset_tick(fresh, observe, self._state)
        elif observe and observed is None:  # started, with observations too large to keep
            observed = self._runner.render(fresh)
        return fresh, levels, observed if observe else None

    def _start_levels(self, compiled: TensorDict) -> tuple[TensorDict, torch.Tensor]:
        """``compiled`` envs after their reset tick, with their observations: the bank keeps
        recurring levels so where the game's reset tick is seed-free."""
        return self._runner.reset_tick(compiled, True, self._state)

    def _step(self, tensordict: TensorDictBase) -> TensorDict:
        state = self.state
        given = tensordict.get("action")
        action = self._check_action(given)
        self._steps += 1
        ahead, self._step_ahead = self._step_ahead, None
        if ahead is not None:
            ran, observed, outputs = ahead
            if ran is not given and not torch.equal(ran, action):
                raise RuntimeError(
                    "gvgai_env.py: a step run ahead was given another action than the one it ran"
                )
            return self._output(observed, outputs)
        return self._output(*self._runner.step(state, action, self._steps))

    def run_step_ahead(
        self, action: torch.Tensor, observed: torch.Tensor, outputs: dict[str, torch.Tensor]
    ) -> None:
        """Take the next step of ``action`` (``[B]`` int64) as already run on ``state`` by the caller,
        with the observation ``observed`` and ``outputs`` (``episode_outputs`` with the reward, after
        ``next_steps``): the fused rollout (``gvgai_pcg.rl.fused``) ticks in its own compiled call,
        and the env's step (``step_and_maybe_reset``, transforms and resets included) then only
        outputs it. The step must be the next ``step`` of exactly that action."""
        self._step_ahead = (action, observed, outputs)

    @property
    def next_steps(self) -> torch.Tensor:
        """``[B]`` int64: each env's step count after its next step (the truncation's clock)."""
        return self._steps + 1

    def _reset_output(self, state: TensorDict, observed: torch.Tensor, restarted: torch.Tensor) -> TensorDict:
        """The reset's output for every env of ``state``, whose observation is ``observed``. Envs
        where ``restarted`` (``[B]`` bool) is true have just been reset: none of them is done (a
        Frogs level without goals is won at its reset tick, but its episode only ends at the next
        step)."""
        return self._output(observed, episode_outputs(state, self._steps, self.max_steps, ~restarted))

    def _output(self, observed: torch.Tensor, outputs: dict[str, torch.Tensor]) -> TensorDict:
        """The env's output: the observation ``observed``, ``outputs`` (``episode_outputs``, and
        the reward after a step) and the env's own entries."""
        self._observed = observed  # a partial reset keeps it for the envs it does not restart
        if self._own_entries is None:
            # Only a reset changes them: the outputs until the next reset share these copies.
            self._own_entries = {
                "difficulty": self._difficulty.unsqueeze(-1).clone(),
                "level_seed": self._level_seeds.to(self.device, copy=True).unsqueeze(-1),
                "level_difficulty": self._level_difficulties.to(self.device, copy=True).unsqueeze(-1),
            }
        values = {self.obs_kind: observed, **outputs, **self._own_entries}
        # Every entry is [num_envs, ...] on self.device: the checks would cost a third of this method.
        return unchecked_tensordict(values, self.batch_size, self.device)

    def _set_seed(self, seed: int | None) -> int | None:
        if seed is not None:
            self._env_seeds = derive_seeds(int(seed), self.num_envs)
            self._episodes.zero_()
            if self._prepared_resets is not None:
                self._prepared_resets.clear()
        return seed

    # --- looking at an env ---
    def render(self, index: int = 0, mode: str = "rgb_array") -> np.ndarray | str:
        """Env ``index`` as an RGB array ``[10H, 10W, 3]`` (mode ``rgb_array``) or text (``ansi``)."""
        if mode == "ansi":
            return ascii_frame(self.game, self.state, index)
        if mode != "rgb_array":
            raise ValueError(f"unknown render mode {mode!r}; valid modes are: rgb_array, ansi")
        frame = render_pixels(self.game, self.state[index : index + 1])[0]
        return frame.permute(1, 2, 0).cpu().numpy()
