"""How fast does Zelda step when its levels hold many monsters, as ACCEL's edited levels do?
(a measurement, not part of the package.)

Adds N monsters to each of the five human levels with Zelda's editor, then steps 64 envs with
random actions (resets included) on one torch thread and prints the monster table's width and the
env steps per CPU second of this process (median of 5 windows of 100 steps, after 300 warm-up
steps): CPU time, since the machine it was measured on was busy with training runs. Run it with
``GVGAI_PCG_COMPILE=0`` for the eager tick; with ``--always-compiled`` the crowded check is
switched off, so the compiled tick runs whatever the width (the engine before
``COMPILED_MONSTER_SLOTS``; run against a checkout from before it, with PYTHONPATH, the option
changes nothing).

Usage: python docs/experiments/crowded_zelda.py N [ENVS] [--always-compiled]

Measured at main @ f2365f4 and the commit after it (2026-11-29, the second core busy with a training run):
docs/history/benchmarks-notebook.md, "Crowded Zelda levels".
"""

from __future__ import annotations

import statistics
import sys
import time

import numpy as np
import torch

import gvgai_pcg.games.zelda.rules as zelda_rules
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games.editing import Grid
from gvgai_pcg.games.zelda import editor
from gvgai_pcg.levels import human_levels
from gvgai_pcg.levels.level import Level


def crowded_levels(monsters: int, seed: int = 0) -> list[Level]:
    rng = np.random.default_rng(seed)
    levels = []
    for level in human_levels("zelda"):
        grid = Grid(level)
        for _ in range(monsters):
            editor.add_monster(grid, rng)
        levels.append(grid.level())
    return levels


def main() -> None:
    args = [arg for arg in sys.argv[1:] if not arg.startswith("--")]
    added, batch = int(args[0]), int(args[1]) if len(args) > 1 else 64
    if "--always-compiled" in sys.argv and hasattr(zelda_rules, "COMPILED_MONSTER_SLOTS"):
        zelda_rules.COMPILED_MONSTER_SLOTS = 10**9
    torch.set_num_threads(1)
    env = GVGAIEnv("zelda", num_envs=batch, levels=crowded_levels(added), obs="tiles", seed=0)
    generator = torch.Generator().manual_seed(0)
    td = env.reset()

    def run(steps: int) -> None:
        nonlocal td
        for _ in range(steps):
            td.set("action", torch.randint(0, env.game.num_actions, (batch,), generator=generator))
            _, td = env.step_and_maybe_reset(td)

    run(300)
    rates = []
    for _ in range(5):
        begin = time.process_time()
        run(100)
        rates.append(100 * batch / (time.process_time() - begin))
    width = env._state.get("monsters").batch_size[1]  # noqa: SLF001 (a measurement)
    print(
        f"monsters added {added}, table width {width}, B={batch}: "
        f"{statistics.median(rates):,.0f} steps per CPU s (windows {min(rates):,.0f}-{max(rates):,.0f})"
    )


if __name__ == "__main__":
    main()
