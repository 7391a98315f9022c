"""Zelda: take the key, reach the door; the sword kills monsters (RULES.md §4, GENERATORS.md §1.2).

The game is this folder: ``rules`` (the ``Game``), ``generator`` (its constructive level
generator), ``editor`` (its small level edits, for ACCEL), ``checks`` (what a generated level
contains and must hold), ``human_levels/`` (the study's five human-designed levels) and
``test_sets/`` (the frozen evaluation levels, with their manifest). ``SPEC`` names them for the
registry (``gvgai_pcg.games.registry``).
"""

from gvgai_pcg.games.spec import GameSpec, LevelFormat, StepFacts, WinNeed
from gvgai_pcg.games.zelda import checks

# The door (g) opens with the key (+); no door left is a win at the first tick.
LEVEL_FORMAT = LevelFormat(
    "zelda",
    "w.A+g123",
    "A",
    height=9,
    width=13,
    win_needs=(WinNeed("+", 1, "key (+)"), WinNeed("g", 1, "goal (g)")),
)

SPEC = GameSpec(
    name="zelda",
    title="Zelda",
    level_format=LEVEL_FORMAT,
    rules="gvgai_pcg.games.zelda.rules:Zelda",
    generator="gvgai_pcg.games.zelda.generator:generate",
    editor="gvgai_pcg.games.zelda.editor:edit",
    counts=checks.counts,
    playability_problems=checks.playability_problems,
    study_tileset="wAg+123",
    data_package=__name__,
    human_levels=5,
    study_index=0,
    bench_target=250_000,
    frame_cost=1.0,
    step_facts=StepFacts(compiles=True, eager_when=("crowded",)),
)
