"""Solarfox: collect every blib; enemies shoot, walls kill (RULES.md §5, GENERATORS.md §1.3).

The game is this folder: ``rules`` (the ``Game``), ``generator`` (its constructive level
generator), ``editor`` (its small level edits, for ACCEL), ``checks`` (what a generated level
contains and must hold), ``human_levels/`` (the study's five human-designed levels) and
``test_sets/`` (the frozen evaluation levels, with their manifest). ``SPEC`` names them for the
registry (``gvgai_pcg.games.registry``).
"""

from gvgai_pcg.games.solarfox import checks
from gvgai_pcg.games.spec import GameSpec, LevelFormat, StepFacts, WinNeed

# Won when no pill (blib b, powerblib p) is left.
LEVEL_FORMAT = LevelFormat(
    "solarfox", "w+.bpA21", "A", height=11, width=10, win_needs=(WinNeed("bp", 1, "pill (b or p)"),)
)

SPEC = GameSpec(
    name="solarfox",
    title="Solarfox",
    level_format=LEVEL_FORMAT,
    rules="gvgai_pcg.games.solarfox.rules:Solarfox",
    generator="gvgai_pcg.games.solarfox.generator:generate",
    editor="gvgai_pcg.games.solarfox.editor:edit",
    counts=checks.counts,
    playability_problems=checks.playability_problems,
    study_tileset="wAp+b12",
    data_package=__name__,
    human_levels=5,
    study_index=1,
    bench_target=250_000,
    frame_cost=0.85,
    # Above 2,048 envs its compiled tick stops paying: the env stepped 1.08x as fast at B = 2,048
    # and 1.02x at 4,096 on 2 threads, 0.98x and 0.84x on one (docs/history/benchmarks-notebook.md;
    # `python -m gvgai_pcg.bench.compiled solarfox 2048 4096`).
    step_facts=StepFacts(compiles=True, max_compiled_batch=2048),
)
