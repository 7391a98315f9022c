"""What a curriculum would replay next (``Curriculum.replay_levels``, the comparison's pictures):
PLR⊥'s and SFL's best levels first, ACCEL's by content, none from an empty buffer."""

from __future__ import annotations

import torch

from gvgai_pcg.curricula import get_curriculum
from gvgai_pcg.curricula.accel import encode_level
from gvgai_pcg.generators import generate_level

SECTION = {"buffer_size": 8}


def test_plr_replays_its_highest_scores_first_as_generated():
    plr = get_curriculum("plr")
    buffer = plr.make_state("zelda", SECTION)
    assert plr.replay_levels(buffer, 3) == []  # empty: nothing to show
    for seed, score in [(11, 0.1), (12, 0.9), (13, 0.5)]:
        buffer.insert(seed, 0.5, score, 0.0)
    shown = plr.replay_levels(buffer, 2)
    assert shown == [generate_level("zelda", 0.5, 12), generate_level("zelda", 0.5, 13)]


def test_accel_shows_its_levels_by_content():
    accel = get_curriculum("accel")
    buffer = accel.make_state("zelda", SECTION)
    level = generate_level("zelda", 1.0, 5)
    edited = type(level)("zelda", (level.rows[0], *level.rows[1:]))
    buffer.insert(
        2**50, 1.0, 0.7, 0.0, content=encode_level(edited, buffer.content.shape[1], buffer.content.shape[2])
    )
    assert [shown.rows for shown in accel.replay_levels(buffer, 4)] == [edited.rows]


def test_sfl_shows_its_most_learnable_levels_first():
    sfl = get_curriculum("sfl")
    buffer = sfl.make_state("frogs", {"buffer_size": 4})
    assert sfl.replay_levels(buffer, 2) == []
    buffer.replace(torch.tensor([0.2, 0.8]), torch.tensor([3, 4]), torch.tensor([0.09, 0.25]), frames=0)
    assert sfl.replay_levels(buffer, 2) == [generate_level("frogs", 0.8, 4), generate_level("frogs", 0.2, 3)]
