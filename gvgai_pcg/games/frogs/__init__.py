"""Frogs: cross the road and the river to the goal (RULES.md §6, GENERATORS.md §1.4).

The game is this folder: ``rules`` (the ``Game``), ``generator`` (its constructive level
generator), ``editor`` (its small level edits, for ACCEL), ``checks`` (what a generated level
contains and must hold), ``human_levels/`` (the study's five human-designed levels) and
``test_sets/`` (the frozen evaluation levels, with their manifest). ``SPEC`` names them for the
registry (``gvgai_pcg.games.registry``).
"""

from gvgai_pcg.games.frogs import checks
from gvgai_pcg.games.spec import GameSpec, LevelFormat, StepFacts, WinNeed

# Won when the goal (g) is reached; no goal left is a win at the first tick.
LEVEL_FORMAT = LevelFormat(
    "frogs", "w+.g0=1234BA-x_l", "AB", height=11, width=28, win_needs=(WinNeed("g", 1, "goal (g)"),)
)

SPEC = GameSpec(
    name="frogs",
    title="Frogs",
    level_format=LEVEL_FORMAT,
    rules="gvgai_pcg.games.frogs.rules:Frogs",
    generator="gvgai_pcg.games.frogs.generator:generate",
    editor="gvgai_pcg.games.frogs.editor:edit",
    counts=checks.counts,
    playability_problems=checks.playability_problems,
    study_tileset="wAg+x0=-4321l",
    data_package=__name__,
    human_levels=5,
    study_index=2,
    bench_target=150_000,
    frame_cost=1.8,
    # Miscompile opt-out: compiled for CUDA (torch 2.11, H200) the tick matched the
    # CPU's for 80 ticks of a mixed batch, but in an env of generated levels, whose resets
    # recompile it for new table widths, the tiles differed from the CPU's at step 29; the eager
    # CUDA tick matched for all 80. Reproduce on a GPU with "cuda" added here:
    # `python -m gvgai_pcg.bench.device_check`.
    step_facts=StepFacts(compiles=True, compiled_devices=("cpu",)),
)
