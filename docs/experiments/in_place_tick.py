"""Would the compiled tick be cheaper if it wrote its new leaves into the state's own tensors?
(issue 38; a measurement, not part of the package: it reaches into ``GVGAIEnv``'s internals.)

A: the engine's fused call as it is (``CompiledTick.tick_and_draw``). The tick replaces leaves of
   the state (``state.set``), so each replaced leaf is an output of the graph: a fresh buffer
   every call, and dynamo puts it back into the TensorDict afterwards.
B: the same tick on a shallow copy of the state, after which each replaced leaf is copied into
   the state's own tensor (``copy_``, an input mutation the graph keeps), so fewer outputs.
   One trap: where the tick hands one leaf's old tensor to another key (Zelda's ``lastx = x``),
   the copies come out wrong once compiled (the copy into ``x`` lands before the copy that reads
   the old ``x``, clone or not); those keys are set by reference, as the tick did.

Usage: python docs/experiments/in_place_tick.py GAME ENVS [--env]
Checks B against A (tiles and outputs) and both against the eager tick (every state leaf) over
300 ticks, then prints process-CPU µs a call for A and B over 16 alternating windows of 300 calls.
With ``--env``: µs an env step (``step_and_maybe_reset``, human levels, random actions) over 10
windows of 500 steps, the env's fused call swapped between A and B from window to window.

Measured at main @ 4f606c8 (2026-11-29): a point-in-time script, not kept in step with the
package; docs/history/benchmarks-notebook.md has its numbers.
"""

from __future__ import annotations

import sys
import time

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.compiled import INDUCTOR_OPTIONS
from gvgai_pcg.engine.outputs import episode_outputs
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games.render import render_tiles_traced


def leaves(td: TensorDict, prefix: tuple = ()):
    for key, value in td.items():
        if isinstance(value, TensorDict):
            yield from leaves(value, (*prefix, key))
        else:
            yield (*prefix, key), value


def write_back(state: TensorDict, work: TensorDict) -> None:
    """Each leaf the tick replaced in ``work`` copied into ``state``'s own tensor; a tensor that
    changed keys (and the key it left) by reference."""
    olds, news = dict(leaves(state)), dict(leaves(work))
    taken = [leaf for leaf in news.values() if any(leaf is old for old in olds.values())]
    for key, leaf in news.items():
        old = olds[key]
        if leaf is old:
            continue
        if any(leaf is t for t in taken) or any(old is t for t in taken):
            state.set(key, leaf)
        else:
            old.copy_(leaf)


def tick_and_draw_in_place(game, state, action, steps, max_steps, **arguments):
    work = state.clone(False)
    before = state.get("score").clone()
    type(game).tick(game, work, action, **arguments)
    write_back(state, work)
    return render_tiles_traced(game, state), episode_outputs(state, steps, max_steps, score_before=before)


def main(game_name: str, n: int) -> None:
    torch.set_num_threads(1)
    env = GVGAIEnv(game_name, num_envs=n, levels="human", seed=0)
    env.reset()
    tick = env._runner.compiled_tick
    in_place = torch.compile(tick_and_draw_in_place, fullgraph=True, dynamic=True, options=INDUCTOR_OPTIONS)
    state0 = env.state.clone()
    steps = torch.zeros(n, dtype=torch.int64)
    actions = torch.randint(0, env.game.num_actions, (300, n), generator=torch.Generator().manual_seed(0))

    def a(state, action):
        return tick.tick_and_draw(state, action, steps, 2000)

    def b(state, action):
        arguments, _ = tick._arguments(state, "cpu")
        return in_place(env.game, state, action, steps, 2000, **arguments)

    sa, sb, se = state0.clone(), state0.clone(), state0.clone()
    for action in actions:
        oa, ob = a(sa, action), b(sb, action)
        env.game.tick(se, action, **tick._arguments(se, "cpu")[0])
        assert torch.equal(oa[0], ob[0]) and all(torch.equal(oa[1][k], ob[1][k]) for k in oa[1])
    for key in sa.keys(True, True):
        assert torch.equal(sa.get(key), se.get(key)) and torch.equal(sb.get(key), se.get(key)), key
    print("A, B and the eager tick agree over 300 ticks")
    times: dict[str, list[float]] = {"A": [], "B": []}
    for window in range(16):
        order = (("A", a), ("B", b)) if window % 2 == 0 else (("B", b), ("A", a))
        for name, call in order:
            state = state0.clone()
            start = time.process_time()
            for action in actions:
                call(state, action)
            times[name].append((time.process_time() - start) / len(actions) * 1e6)
    for name, values in times.items():
        print(name, game_name, n, " ".join(f"{v:.0f}" for v in sorted(values)))


def env_steps(game_name: str, n: int, steps: int = 500, windows: int = 10) -> None:
    torch.set_num_threads(1)
    env = GVGAIEnv(game_name, num_envs=n, levels="human", seed=0)
    tick = env._runner.compiled_tick
    calls = {
        "A": tick._compiled_and_drawn,
        "B": torch.compile(tick_and_draw_in_place, fullgraph=True, dynamic=True, options=INDUCTOR_OPTIONS),
    }
    td = env.reset()
    actions = torch.randint(0, env.game.num_actions, (steps, n), generator=torch.Generator().manual_seed(0))

    def play(name: str, count: int) -> float:
        nonlocal td
        tick._compiled_and_drawn = calls[name]
        start = time.process_time()
        for action in actions[:count]:
            td.set("action", action)
            _, td = env.step_and_maybe_reset(td)
        return (time.process_time() - start) / count * 1e6

    for name in calls:  # compile both
        play(name, 300)
    times: dict[str, list[float]] = {"A": [], "B": []}
    for window in range(windows):
        for name in ("A", "B") if window % 2 == 0 else ("B", "A"):
            times[name].append(play(name, steps))
    for name, values in times.items():
        values = sorted(values)
        shown = " ".join(f"{v:.0f}" for v in values)
        print(name, game_name, n, "median", f"{values[len(values) // 2]:.0f}", shown)


if __name__ == "__main__":
    (env_steps if "--env" in sys.argv else main)(sys.argv[1], int(sys.argv[2]))
