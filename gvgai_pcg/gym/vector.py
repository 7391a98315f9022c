"""``GVGAIVectorEnv``: the batched engine behind Gymnasium's ``VectorEnv`` API.

Not N copies of a single env: one ``GVGAIEnv`` with a batch of ``num_envs`` advances every env
in one tick, and finished envs are restarted with a partial reset (the ``"_reset"`` mask). So a
Gymnasium user gets the engine's speed, and for the same seed and actions the steps equal the
TorchRL env's (``GVGAIEnv(game, num_envs, seed=s)``; with ``SAME_STEP`` autoreset they match
``step_and_maybe_reset`` step for step).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np
import torch
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space
from tensordict import TensorDict, TensorDictBase

import gvgai_pcg.envs.quiet_torchrl  # noqa: F401 (first: torchrl without its global side effect)
from gvgai_pcg.engine.step_plan import COMPILE_PAYS_BACK_STEPS, choose_step_plan, compile_pays_back
from gvgai_pcg.envs.gvgai_env import GVGAIEnv
from gvgai_pcg.gym.adapter import LevelSetSpec, LevelSpec, Regimen, observation_space

INFO_KEYS = ("won", "score", "difficulty", "level_seed")
TENSORDICT_KEYS = {"difficulty": "level_difficulty"}  # the d a level was made at (DR draws it per level)
DONE_KEYS = ("done", "terminated", "truncated")
INFO_DTYPES = {"won": np.bool_, "score": np.float64, "difficulty": np.float64, "level_seed": np.int64}


class GVGAIVectorEnv(VectorEnv):
    """``num_envs`` envs of one game, stepped together (``gymnasium.make_vec("gvgai_pcg/Zelda-v0", 8)``).

    Takes the single env's arguments (see ``GVGAIGymEnv``) plus ``autoreset_mode``:
    ``NEXT_STEP`` (Gymnasium's default: the step after an episode ends returns the new episode's
    first observation, with reward 0) or ``SAME_STEP`` (the ending step already returns the new
    episode's first observation; the last one is in ``info["final_obs"]``). ``info`` holds
    ``won``, ``score``, ``difficulty`` and ``level_seed`` as ``[N]`` arrays.

    ``total_steps``: the batched steps (``step`` calls) the job will take, if known. Compiling the
    tick costs half a minute and pays back only past ``COMPILE_PAYS_BACK_STEPS`` of them on the CPU
    (the decision ``gvgai-pcg train`` takes from its frames), so a job that is shorter, or does not
    say, ticks eagerly; a long one that says so ticks compiled, about twice as fast per step. A
    job that did not say is told once, with a warning, when it passes that many steps.
    """

    metadata = {"render_modes": ["rgb_array", "ansi"], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        num_envs: int = 1,
        game: str = "zelda",
        regimen: str = "human",
        difficulty: float | None = None,
        obs: str = "tiles",
        render_mode: str | None = None,
        level: LevelSpec | Sequence[LevelSpec] = 0,
        max_steps: int = 2000,
        alpha: float | None = None,
        win_rule: str = "game",
        device: str = "cpu",
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        levels: LevelSetSpec | None = None,
        num_levels: int = 0,
        start_seed: int = 0,
        total_steps: int | None = None,
    ) -> None:
        if total_steps is not None and (not isinstance(total_steps, int | np.integer) or total_steps < 0):
            raise ValueError(f"total_steps must be a whole number >= 0 (batched steps), got {total_steps!r}")
        autoreset_mode = AutoresetMode(autoreset_mode)
        if autoreset_mode == AutoresetMode.DISABLED:
            raise ValueError("autoreset_mode DISABLED is not supported; use NEXT_STEP or SAME_STEP")
        modes = self.metadata["render_modes"]
        if render_mode is not None and render_mode not in modes:
            raise ValueError(f"unknown render mode {render_mode!r}; valid modes are: {', '.join(modes)}")
        self.metadata = {**self.metadata, "autoreset_mode": autoreset_mode}
        self.autoreset_mode, self.render_mode, self.num_envs = autoreset_mode, render_mode, num_envs
        self.regimen = Regimen(
            game, regimen, num_envs, level, difficulty, alpha, win_rule, levels, num_levels, start_seed
        )
        self.engine = GVGAIEnv(
            game,
            num_envs,
            self.regimen.source,
            obs=obs,
            max_steps=max_steps,
            device=device,
            difficulty=self.regimen.difficulty,
            compile_tick=compile_pays_back(int(total_steps or 0), device),
        )
        self.obs_kind = obs
        # a job that did not give its length, on an env that would compile: told when it is long
        self._steps_taken = 0
        self._tell_at = None
        if total_steps is None and not self.engine.step_plan.compiled:
            would = choose_step_plan(self.engine.game, num_envs, self.engine.device, obs).compiled
            self._tell_at = COMPILE_PAYS_BACK_STEPS if would else None
        self.single_observation_space = observation_space(game, obs)
        self.single_action_space = gym.spaces.Discrete(self.engine.game.num_actions)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._autoreset = torch.zeros(num_envs, dtype=torch.bool)
        self._started = False
        self._kept_keys = (obs, *(TENSORDICT_KEYS.get(key, key) for key in INFO_KEYS))
        self._last: TensorDictBase | None = None  # the latest observation and info, for partial resets

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Reset every env, or those in ``options["reset_mask"]``. ``seed`` is one int: env i then
        plays with ``GVGAIEnv``'s i-th derived seed. ``options`` also takes ``level`` (this
        episode's) and ``difficulty`` (from now on; see ``GVGAIGymEnv.reset``), each one value for
        every env or a list of ``num_envs`` that the resetting envs take their own entry of: a level
        per env (``None``: the regimen's), a difficulty per env (``regimen="pcg"``)."""
        if seed is not None and not isinstance(seed, int | np.integer):
            raise ValueError(f"seed must be one int (env seeds are derived from it), got {seed!r}")
        options = options or {}
        checked = self.regimen.check_options(options, vector=True)  # a bad option changes nothing
        mask = torch.ones(self.num_envs, dtype=torch.bool)
        if options.get("reset_mask") is not None:
            mask = torch.as_tensor(_reset_mask(options["reset_mask"], self.num_envs))
        super().reset(seed=seed)
        if seed is not None:
            self.engine.set_seed(int(seed))
        elif not self._started:
            self.engine.set_seed(int(self.np_random.integers(2**31)))
        if not self._started:
            mask = torch.ones(self.num_envs, dtype=torch.bool)
        self._started = True
        self.regimen.apply_options(checked, mask.nonzero().flatten().tolist())
        self.regimen.restart(mask)
        out = self._reset_engine(mask.to(self.engine.device), self._last)
        if self._last is not None and not bool(mask.all()):
            out = _take(mask.to(self.engine.device), out, self._last, self._kept_keys)
        self._autoreset = self._autoreset & ~mask
        self._last = out.select(*self._kept_keys, *DONE_KEYS)
        return self._obs(out), self._info(out)

    def step(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        if not self._started:
            raise RuntimeError("call reset() before step()")
        device = self.engine.device
        if not self.action_space.contains(np.asarray(actions)):
            highest = self.engine.game.num_actions - 1
            raise ValueError(f"invalid actions {actions!r}; {self.num_envs} integers in 0..{highest}")
        action = torch.as_tensor(np.asarray(actions), dtype=torch.int64, device=device).reshape(self.num_envs)
        self._steps_taken += 1
        if self._steps_taken == self._tell_at:
            warnings.warn(
                f"this job has stepped {self._steps_taken:,} times with the tick eager; a job this long "
                "steps about twice as fast compiled: pass total_steps=<the steps it will take> to "
                "gymnasium.make_vec",
                stacklevel=2,
            )
        out = self.engine.step(TensorDict({"action": action}, batch_size=[self.num_envs], device=device))
        out = out.get("next")
        restarting = self._autoreset.to(device)
        if self.autoreset_mode == AutoresetMode.NEXT_STEP and bool(restarting.any()):
            fresh = self._reset_engine(restarting, out)
            out = self._merge(restarting, fresh, out)
        done = out["done"].reshape(self.num_envs) & ~restarting
        self.regimen.record(out, done, stepped=~restarting.cpu())
        infos: dict[str, Any] = {}
        if self.autoreset_mode == AutoresetMode.SAME_STEP and bool(done.any()):
            infos = self._final_infos(out, done)
            fresh = self._reset_engine(done, out)
            out = _take(done, fresh, out, self._kept_keys)
            self._autoreset = torch.zeros(self.num_envs, dtype=torch.bool)
        else:
            self._autoreset = done.cpu()
        infos.update(self._info(out))
        self._last = out.select(*self._kept_keys, *DONE_KEYS)
        return (
            self._obs(out),
            out["reward"].reshape(self.num_envs).cpu().numpy().astype(np.float64),
            out["terminated"].reshape(self.num_envs).cpu().numpy(),
            out["truncated"].reshape(self.num_envs).cpu().numpy(),
            infos,
        )

    def _reset_engine(self, mask: torch.Tensor, running: TensorDictBase | None) -> TensorDictBase:
        """The engine's reset of the envs in ``mask``, told the running done entries: TorchRL
        warns about a partial reset that leaves done envs it was not shown (here, those that
        finished in the step before a NEXT_STEP reset, which restart at the next one)."""
        request = self.regimen.reset_tensordict(mask, self.engine.device)
        if running is not None:
            request.update(running.select(*DONE_KEYS, strict=False))
        return self.engine.reset(request)

    def _merge(self, mask: torch.Tensor, fresh: TensorDictBase, stepped: TensorDictBase) -> TensorDictBase:
        """The step's output where ``mask`` envs show their new episode: first obs, reward 0, not done."""
        merged = _take(mask, fresh, stepped, self._kept_keys)
        column = mask.reshape(-1, 1)
        merged.set("reward", torch.where(column, torch.zeros_like(stepped["reward"]), stepped["reward"]))
        for key in ("terminated", "truncated", "done"):
            merged.set(key, stepped[key] & ~column)
        return merged

    def _final_infos(self, out: TensorDictBase, done: torch.Tensor) -> dict[str, Any]:
        mask = done.cpu().numpy()
        final_obs = np.full(self.num_envs, None, dtype=object)
        observations = self._obs(out)
        for i in np.flatnonzero(mask):
            final_obs[i] = observations[i]
        final_info = self._info(out)
        for key in INFO_KEYS:
            final_info[f"_{key}"] = mask.copy()
        return {
            "final_obs": final_obs,
            "_final_obs": mask,
            "final_info": final_info,
            "_final_info": mask.copy(),
        }

    def _obs(self, td: TensorDictBase) -> np.ndarray:
        return td[self.obs_kind].cpu().numpy().copy()

    def _info(self, td: TensorDictBase) -> dict[str, Any]:
        info: dict[str, Any] = {}
        for key in INFO_KEYS:
            info[key] = (
                td[TENSORDICT_KEYS.get(key, key)]
                .reshape(self.num_envs)
                .cpu()
                .numpy()
                .astype(INFO_DTYPES[key])
            )
            info[f"_{key}"] = np.ones(self.num_envs, dtype=bool)
        return info

    def render(self) -> tuple[np.ndarray, ...] | tuple[str, ...] | None:
        """One frame per env (``rgb_array``: ``[10H, 10W, 3]`` arrays; ``ansi``: text)."""
        if self.render_mode is None:
            return None
        return tuple(self.engine.render(i, self.render_mode) for i in range(self.num_envs))


def _take(
    mask: torch.Tensor, source: TensorDictBase, target: TensorDictBase, keys: Sequence[str]
) -> TensorDictBase:
    """A copy of ``target`` whose ``keys`` come from ``source`` where ``mask`` (``[B]`` bool)."""
    merged = target.clone()
    for key in keys:
        where = mask.reshape(-1, *([1] * (source[key].dim() - 1)))
        merged.set(key, torch.where(where, source[key], target[key]))
    return merged


def _reset_mask(value: Any, num_envs: int) -> np.ndarray:
    """The ``reset_mask`` option as ``[num_envs]`` bool, or a clear error."""
    mask = np.asarray(value)
    if mask.shape != (num_envs,) or mask.dtype != np.bool_:
        raise ValueError(f"reset_mask must be {num_envs} booleans, got {value!r}")
    return mask
