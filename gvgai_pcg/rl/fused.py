"""The fused rollout step: the acting pass, the sampling and the env's tick as one compiled call.

``ActingRollouts`` pays per step for the network's eager acting pass (a few dozen small ops) and
then for the env's compiled tick as a call of its own. The JAX trainers (PureJaxRL, Craftax,
XLand-MiniGrid) jit the acting pass, the sampling and the env step together; ``FusedStep`` does the
same with ``torch.compile``: the network's forward, the categorical draw and the game's tick with
its outputs (and, for tiles, their render) in one graph.

What stays in Python is what must: the level choice of the envs that finished. The compiled call
runs the step ahead and hands it to the env (``GVGAIEnv.run_step_ahead``); the env's
``step_and_maybe_reset`` then outputs it through the transforms as any step, and restarts the
finished envs with their next levels (prepared episodes, PPCG's difficulty, PLR's picks) exactly as
the unfused path does. So every curriculum rolls out fused, and the rollouts are the same tensors:
the same ops on the same inputs, and the same draws (``fallback_random``: inductor calls the eager
``multinomial``, which reads the global generator as the unfused step does).

A step whose data asks for the eager tick (``StepFacts.eager_when``) runs the same function
eagerly; where compiling fails, every step does from then on (with one warning).

It is not faster on the CPU, so training uses it only when asked (``rollout=fused``; ``auto`` rolls
out unfused): inductor's CPU code for the compact network is slower than eager, more so with the
acting graph kept, and that costs more than the tick's per-call wall it saves. docs/training.md
has the measured figures.
"""

from __future__ import annotations

import warnings

import torch
from tensordict import TensorDict
from torch import nn

from gvgai_pcg.engine.compiled import COMPILE_ERRORS, INDUCTOR_OPTIONS, configure_compiler_thread
from gvgai_pcg.engine.outputs import episode_outputs
from gvgai_pcg.envs.gvgai_env import GVGAIEnv
from gvgai_pcg.games.base import Game
from gvgai_pcg.games.render import render_tiles_traced
from gvgai_pcg.rl.rollout import sample_actions

# fallback_random: the compiled draw is eager multinomial's (same generator, same numbers).
FUSED_OPTIONS = {**INDUCTOR_OPTIONS, "fallback_random": True}

Outputs = dict[str, torch.Tensor]


def act_and_tick(
    net: nn.Module,
    game: Game,
    state: TensorDict,
    obs: torch.Tensor,
    steps: torch.Tensor,
    max_steps: int,
    draw_tiles: bool,
    **arguments: object,
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor, torch.Tensor | None, Outputs]:
    """The acting pass on ``obs``, its sampled actions and the tick of ``state`` they take (in
    place), with ``episode_outputs`` after ``steps`` and the tiles if ``draw_tiles``: what
    ``FusedStep`` compiles. Returns ``logits, value, action, tiles | None, outputs``."""
    logits, value = net(obs)
    action = sample_actions(logits)
    before = state.get("score").clone()
    type(game).tick(game, state, action, **arguments)
    tiles = render_tiles_traced(game, state) if draw_tiles else None
    return logits, value, action, tiles, episode_outputs(state, steps, max_steps, score_before=before)


def fused_env(env) -> GVGAIEnv | None:
    """The ``GVGAIEnv`` under ``env``'s transforms, or None where ``env`` is not one."""
    base = getattr(env, "base_env", env)
    return base if isinstance(base, GVGAIEnv) else None


def fusable(env) -> str | None:
    """Why ``env`` cannot roll out fused (None where it can): it must be one natively batched
    ``GVGAIEnv`` (under any transforms) that ticks in one thread of this process. An env that
    ticks eagerly rolls out fused eagerly: the same ops, in the same order."""
    base = fused_env(env)
    if base is None:
        return f"{type(env).__name__} is not a GVGAIEnv"
    if base.step_plan.large_graph or base._runner.sharded.shards > 1:
        return f"its tick runs on several threads ({base.step_plan})"
    return None


class FusedStep:
    """One step of ``env`` acted by ``net``: ``act_and_tick`` compiled (or eager where ``compile``
    is false: the same ops, for tests and for envs that tick eagerly), handed to the env as its
    next step."""

    def __init__(self, env, net: nn.Module, compile: bool = True) -> None:
        base = fused_env(env)
        if base is None:
            raise ValueError(f"fused.py: a fused rollout needs a GVGAIEnv, not {type(env).__name__}")
        self.env, self.net, self.game = base, net, base.game
        self.draw_tiles = base.obs_kind == "tiles" and base.step_plan.fused
        self._compiled = (
            torch.compile(act_and_tick, fullgraph=True, dynamic=True, options=FUSED_OPTIONS)
            if compile
            else None
        )
        self.failed: str | None = None

    def __call__(self, obs: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Act on ``obs`` (the env's current observation) and run the env's next step ahead;
        returns ``logits, value, action``. The caller then steps the env with ``action``."""
        env = self.env
        state, steps = env.state, env.next_steps
        arguments = self.game.host_arguments(state)
        eager = self._compiled is None or self.failed is not None
        eager = eager or any(arguments[name] for name in self.game.step_facts.eager_when)
        call = (act_and_tick,) if eager else (self._compiled, act_and_tick)
        result = None
        for function in call:
            try:
                if function is not act_and_tick:
                    configure_compiler_thread()
                result = function(
                    self.net, self.game, state, obs, steps, env.max_steps, self.draw_tiles, **arguments
                )
                break
            except COMPILE_ERRORS as error:  # raised while compiling, before anything ran
                self.failed = str(error).strip().splitlines()[0][:300]
                warnings.warn(
                    f"compiling the fused rollout step failed ({self.failed}); it runs eagerly, "
                    "which computes the same",
                    RuntimeWarning,
                    stacklevel=2,
                )
        logits, value, action, tiles, outputs = result
        observed = tiles if tiles is not None else env._runner.render(state)
        env.run_step_ahead(action, observed, outputs)
        return logits, value, action


def fused_step(rollout: str, env, net: nn.Module) -> FusedStep | None:
    """The fused step of ``env`` and ``net`` where ``rollout`` (the config's ``rollout``) asks for
    it: ``fused``, or a one-line refusal saying why not; None for ``unfused`` and ``auto`` (the
    acting pass runs eagerly: the fused step is not faster on the CPU, see the module docstring)."""
    if rollout != "fused":
        return None
    why_not = fusable(env)
    if why_not is not None:
        raise ValueError(f"rollout=fused: this env cannot roll out fused: {why_not}")
    return FusedStep(env, net, compile=fused_env(env).step_plan.compiled)
