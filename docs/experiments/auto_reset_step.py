"""Would an auto-reset inside the compiled step pay on the CPU? (issue 38 item 3; a measurement,
not part of the package: it reaches into ``GVGAIEnv``'s internals.)

A: the env as it is, driven by TorchRL's ``step_and_maybe_reset`` (what a rollout does).
B: one compiled call (``fullgraph=True``): tick, tiles and outputs, then every state leaf, the
   observation and the step count swapped to the env's prepared next episode where it is done;
   the host then prepares the next episode of the envs that finished (``GVGAIEnv._prepare``,
   padded to the running widths) and builds a minimal output TensorDict.

Usage: python docs/experiments/auto_reset_step.py GAME ENVS [STEPS ROUNDS] [--unsafe]
(``--unsafe`` skips dynamo's guards on B's call). Prints process-CPU µs a step for A and B, and
B's compiled call alone, round by round (A and B alternate).

Measured at main @ 1be7ba7 and 6f66b7f (2026-11-29): a point-in-time script, not kept in step with the
package; docs/history/benchmarks-notebook.md has its numbers.
"""

from __future__ import annotations

import sys
import time

import torch
from tensordict import TensorDict

from gvgai_pcg._private_apis import unchecked_tensordict
from gvgai_pcg.engine.compiled import INDUCTOR_OPTIONS, configure_compiler_thread, tick_and_draw
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.states import entity_capacities, pad_entity_tables


def tick_draw_reset(game, state, next_state, next_obs, action, steps, max_steps, **arguments):
    """The fused step, then each done env's row of every leaf taken from its next episode."""
    obs, out = tick_and_draw(game, state, action, steps, max_steps, **arguments)
    done = out["done"].squeeze(-1)
    for key in state.keys(True, True):
        leaf = state.get(key)
        leaf.copy_(torch.where(done.view(-1, *([1] * (leaf.ndim - 1))), next_state.get(key), leaf))
    first = torch.where(done.view(-1, 1, 1, 1), next_obs, obs)
    steps.copy_(torch.where(done, torch.zeros_like(steps), steps))
    return obs, out, first


COMPILED = torch.compile(tick_draw_reset, fullgraph=True, dynamic=True, options=INDUCTOR_OPTIONS)


class AutoResetStep:
    """B: ``env``'s state stepped by ``tick_draw_reset``, its next episodes kept ready."""

    def __init__(self, env: GVGAIEnv, unsafe: bool) -> None:
        self.env, self.unsafe, self.compiled_s = env, unsafe, 0.0
        self.next_state, self.next_obs = self.prepare(torch.arange(env.num_envs))

    def prepare(self, index: torch.Tensor) -> tuple[TensorDict, torch.Tensor]:
        fresh, _, obs = self.env._prepare(index, True, self.env._episodes[index])
        widths = entity_capacities(self.env.state)
        assert all(w <= widths[k] for k, w in entity_capacities(fresh).items()), "a wider level"
        return pad_entity_tables(fresh, widths), obs

    def step(self, action: torch.Tensor) -> TensorDict:
        env = self.env
        env._steps += 1
        configure_compiler_thread()
        arguments = env.game.host_arguments(env.state)
        start = time.process_time()
        with torch.compiler.set_stance(skip_guard_eval_unsafe=self.unsafe):
            obs, out, first = COMPILED(
                env.game, env.state, self.next_state, self.next_obs, action, env._steps, env.max_steps,
                **arguments,
            )  # fmt: skip
        self.compiled_s += time.process_time() - start
        index = out["done"].squeeze(-1).nonzero().flatten()
        if len(index):
            env._episodes[index] += 1
            fresh, fresh_obs = self.prepare(index)
            for key in self.next_state.keys(True, True):
                self.next_state.get(key)[index] = fresh.get(key)
            self.next_obs[index] = fresh_obs
        return unchecked_tensordict({env.obs_kind: first, **out}, env.batch_size, env.device)


def main() -> None:
    args = [a for a in sys.argv[1:] if a != "--unsafe"]
    game, envs = args[0], int(args[1])
    steps, rounds = (int(args[2]), int(args[3])) if len(args) > 3 else (2000, 3)
    torch.set_num_threads(1)
    env_a, env_b = GVGAIEnv(game, envs, seed=1), GVGAIEnv(game, envs, seed=1)
    td = env_a.reset()
    env_b.reset()
    auto = AutoResetStep(env_b, "--unsafe" in sys.argv)

    def run_a(td: TensorDict, n: int) -> TensorDict:
        for _ in range(n):
            td.set("action", torch.randint(0, env_a.game.num_actions, (envs,)))
            _, td = env_a.step_and_maybe_reset(td)
        return td

    def run_b(n: int) -> None:
        for _ in range(n):
            auto.step(torch.randint(0, env_b.game.num_actions, (envs,)))

    td = run_a(td, 300)  # compiles both
    run_b(300)
    for _ in range(rounds):
        start = time.process_time()
        td = run_a(td, steps)
        a = time.process_time() - start
        auto.compiled_s, start = 0.0, time.process_time()
        run_b(steps)
        b = time.process_time() - start
        print(f"{game} {envs} envs, us a step: A {a / steps * 1e6:.0f}, B {b / steps * 1e6:.0f} "
              f"(its compiled call {auto.compiled_s / steps * 1e6:.0f})")  # fmt: skip


if __name__ == "__main__":
    main()
