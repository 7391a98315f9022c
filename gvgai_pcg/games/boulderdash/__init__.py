"""Boulderdash: collect nine diamonds, reach the exit; boulders fall (RULES.md §7, GENERATORS.md §1.5).

The game is this folder: ``rules`` (the ``Game``), ``generator`` (its constructive level
generator), ``editor`` (its small level edits, for ACCEL), ``checks`` (what a generated level
contains and must hold), ``human_levels/`` (the study's five human-designed levels) and
``test_sets/`` (the frozen evaluation levels, with their manifest). ``SPEC`` names them for the
registry (``gvgai_pcg.games.registry``).
"""

from gvgai_pcg.games.boulderdash import checks
from gvgai_pcg.games.spec import GameSpec, LevelFormat, StepFacts, WinNeed

# The exit (e) opens for an avatar holding 9 diamonds (x).
LEVEL_FORMAT = LevelFormat(
    "boulderdash",
    "w.-eoxcbA",
    "A",
    height=13,
    width=26,
    win_needs=(WinNeed("e", 1, "exit (e)"), WinNeed("x", 9, "diamonds (x)")),
)

SPEC = GameSpec(
    name="boulderdash",
    title="Boulderdash",
    level_format=LEVEL_FORMAT,
    rules="gvgai_pcg.games.boulderdash.rules:Boulderdash",
    generator="gvgai_pcg.games.boulderdash.generator:generate",
    editor="gvgai_pcg.games.boulderdash.editor:edit",
    counts=checks.counts,
    playability_problems=checks.playability_problems,
    study_tileset="wxoc-be",
    # The study's curriculum counts a Boulderdash episode with a score of 20 or more as a win
    # (GENERATORS.md §2).
    study_score_win=20.0,
    data_package=__name__,
    human_levels=5,
    study_index=3,
    bench_target=150_000,
    frame_cost=1.5,
    step_facts=StepFacts(
        compiles=True,
        # Miscompile opt-out: inductor (torch 2.13, CPU) miscompiles the tick of a batch whose
        # sprites may leave the screen: from the first tick that moves the monsters, their
        # positions differ from the eager tick's, or a kernel fails an index check (aot_eager
        # computes it right). Such a batch, rare (every human and generated level is walled in),
        # ticks eagerly. Reproduce with eager_when=() here:
        # `pytest tests/engine/test_compiled.py -k "equals_eager_tick and boulderdash-True"`.
        eager_when=("leaving",),
        # Above 1,024 envs its compiled tick stops paying: the env stepped 1.03-1.06x as fast at
        # B = 1,024 and 0.84x at 4,096 on 2 threads (1.09x and 1.14x on one;
        # docs/history/benchmarks-notebook.md; `python -m gvgai_pcg.bench.compiled boulderdash 1024 4096`).
        max_compiled_batch=1024,
        # Miscompile opt-out: inductor (torch 2.13, CPU) miscompiles the graph of parallel loops
        # for some table widths: 1,024 envs of the human levels, as compiled (33 boulder slots), on
        # 2 threads, fed a kernel an out-of-bounds index at the first tick (docs/history/
        # benchmarks-notebook.md), where the same tables grown to 64 slots ticked as the eager
        # tick does.
        # So Boulderdash keeps the graph of serial loops over the envs at every batch. Reproduce
        # with parallel_graph=True here (and LARGE_BATCH_PER_THREAD at most 512):
        # `python -c "import torch; torch.set_num_threads(2); from gvgai_pcg.envs import GVGAIEnv;
        # GVGAIEnv('boulderdash', 1024).rollout(3)"`.
        parallel_graph=False,
    ),
)
