"""Does ``torch.compile`` speed up the compact network on the CPU? (A measurement, not part of the
package.) The acting pass over one batch of observations and a forward and backward over five
(A2C's update at 5 steps), eager against compiled, alternating, one torch thread.

Usage: python docs/experiments/compiled_network.py GAME [ENVS [HIDDEN]]   (defaults 64, 256)

Measured at main @ 1be7ba7 and 6f66b7f (2026-11-29): a point-in-time script, not kept in step with the
package; docs/history/benchmarks-notebook.md has its numbers.
"""

from __future__ import annotations

import sys
import time

import torch

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.rl.models import make_actor_critic


def main() -> None:
    game = sys.argv[1]
    envs = int(sys.argv[2]) if len(sys.argv) > 2 else 64
    hidden = int(sys.argv[3]) if len(sys.argv) > 3 else 256
    torch.set_num_threads(1)
    env = GVGAIEnv(game, envs)
    obs = env.reset()["tiles"]
    net = make_actor_critic("compact", "tiles", tuple(obs.shape[1:]), env.game.num_actions, hidden)
    compiled = torch.compile(net, dynamic=False)
    update_batch = obs.repeat(5, 1, 1, 1)

    def act(model: torch.nn.Module) -> None:
        with torch.no_grad():
            model(obs)

    def update(model: torch.nn.Module) -> None:
        logits, value = model(update_batch)
        (logits.logsumexp(-1).mean() + value.pow(2).mean()).backward()

    for work in (act, update):  # compile and warm up
        for model in (net, compiled):
            for _ in range(20):
                work(model)
    print(f"{game}, {envs} envs, hidden {hidden}: ms a call, eager / compiled")
    for _ in range(3):
        line = []
        for work, calls in ((act, 200), (update, 60)):
            times = []
            for model in (net, compiled):
                start = time.process_time()
                for _ in range(calls):
                    work(model)
                times.append((time.process_time() - start) / calls * 1e3)
            line.append(f"{work.__name__} {times[0]:.2f} / {times[1]:.2f}")
        print("  " + ", ".join(line))


if __name__ == "__main__":
    main()
