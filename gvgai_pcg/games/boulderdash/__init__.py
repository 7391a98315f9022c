"""Boulderdash: collect nine diamonds, reach the exit; boulders fall (RULES.md §7, GENERATORS.md §1.5).

The game is this folder: ``rules`` (the ``Game``), ``generator`` (its constructive level
generator), ``editor`` (its small level edits, for ACCEL), ``checks`` (what a generated level
contains and must hold), ``human_levels/`` (the study's five human-designed levels) and
``test_sets/`` (the frozen evaluation levels, with their manifest). ``SPEC`` names them for the
registry (``gvgai_pcg.games.registry``).
"""

from gvgai_pcg.games.boulderdash import checks
from gvgai_pcg.games.spec import GameSpec, LevelFormat, WinNeed

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
)
