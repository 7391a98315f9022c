"""How much of the package a replayed reset walks through: the files of gvgai_pcg whose Python
functions a PLR⊥ replay of one env row calls, in a training-like setup (the curriculum's run,
``GVGAIEnv`` with its source, a full buffer). Each file on that path is a layer a reader follows
and a cost every replay pays, so the figure is guarded here: the test fails, with the list, when
the walk grows past it."""

from __future__ import annotations

import sys
from pathlib import Path

import torch

import gvgai_pcg
from gvgai_pcg.curricula import get_curriculum
from gvgai_pcg.envs import GVGAIEnv

PACKAGE = str(Path(gvgai_pcg.__file__).parent) + "/"
# The most files of the package one replayed reset may call into: 25 before the level bank kept
# Zelda's levels started (after their seed-free reset tick, with their first observation), the
# lock of an unshared buffer went and PLR⊥ drew new levels only where it plays one; 14 until the
# entity tables' padding moved beside the state merges that use it and a shared state kept its lock.
WALK_MAX_FILES = 12
BUFFER_SIZE, REPLAYED = 300, 42
SECTION = {
    "name": "plr",
    "buffer_size": BUFFER_SIZE,
    "score": "pvl",
    "temperature": 0.01,  # rank 2 weighs 2**-100 of rank 1: the top-scored level is replayed
    "staleness_coef": 0.0,
    "replay_prob": 1.0,
    "rho": 0.5,
    "min_difficulty": 0.0,
    "max_difficulty": 1.0,
    "robust": True,
}


def files_called(call) -> list[str]:
    """The package files (relative paths) whose Python functions ``call()`` enters."""
    seen: set[str] = set()

    def profile(frame, event, arg):
        if event == "call" and frame.f_code.co_filename.startswith(PACKAGE):
            seen.add(frame.f_code.co_filename[len(PACKAGE) :])

    sys.setprofile(profile)
    try:
        call()
    finally:
        sys.setprofile(None)
    return sorted(seen)


def ended(td, row: int):
    """``td`` with env ``row``'s episode ended (what a step that finished it would leave)."""
    done = torch.zeros_like(td.get("done"))
    done[row] = True
    td.set("done", done)
    return td


def test_a_replayed_reset_walks_through_few_files():
    run = get_curriculum("plr").start("zelda", SECTION)
    for i in range(BUFFER_SIZE):  # a full buffer, level 42 scored highest
        run.state.insert(1000 + i, (i % 10) / 10, 1.0 if i == REPLAYED else 0.0, 0.0)
    env = GVGAIEnv("zelda", 4, run.source(), max_steps=50, seed=3, compile_tick=False)
    td = env.maybe_reset(ended(env.reset(), 0))  # warm-up: level 42 has been played
    td = ended(td, 2)
    files = files_called(lambda: env.maybe_reset(td))
    assert int(td.get("level_seed")[2]) == 1000 + REPLAYED  # the traced reset replayed level 42
    assert int(env._episodes[2]) == 2
    print(f"{len(files)} files:", *files, sep="\n  ")
    assert len(files) <= WALK_MAX_FILES, f"a replayed reset calls into {len(files)} files: {files}"
