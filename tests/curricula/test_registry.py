"""The registry holds the study's regimens, DR and any module of gvgai_pcg.curricula that
defines ``CURRICULUM``; each object answers what the evaluation asks of a run's regimen the way
``gvgai_pcg.evaluation.checkpoints.RunInfo`` does today."""

from __future__ import annotations

from pathlib import Path

import pytest

from gvgai_pcg.config import compose_config
from gvgai_pcg.curricula import get_curriculum, registered_curricula
from gvgai_pcg.evaluation.checkpoints import REGIMEN_LABELS, RunInfo

OVERRIDES = [
    ["regimen=lv", "regimen.level=3"],
    ["regimen=lv0-3"],
    ["regimen=human"],
    ["regimen=pcg", "regimen.difficulty=0.5"],
    ["regimen=pcg", "regimen.num_levels=1"],
    ["regimen=pcg", "regimen.num_levels=100", "regimen.start_seed=7"],
    ["regimen=ppcg"],
    ["regimen=dr"],
]


def test_the_study_regimens_come_first_in_their_order():
    assert list(registered_curricula())[:7] == ["lv", "lv0-3", "human", "levels", "pcg", "ppcg", "dr"]


@pytest.mark.parametrize("overrides", OVERRIDES, ids=" ".join)
def test_it_labels_and_names_training_sets_as_the_evaluation_does(overrides):
    cfg = compose_config(["game=zelda", *overrides])
    config = {"game": {"name": "zelda"}, "regimen": dict(cfg.regimen)}
    run = RunInfo(Path("run"), config, Path("run/model.pt"), 0)
    curriculum = get_curriculum(cfg.regimen.name)
    known = cfg.regimen.name in REGIMEN_LABELS  # the evaluation shows another regimen by its name
    assert (curriculum.row_label(cfg.regimen) if known else cfg.regimen.name) == run.label
    assert curriculum.has_training_set(cfg.regimen) == run.has_training_set
    if not run.has_training_set:
        assert curriculum.human_levels_trained(cfg.regimen) == run.training_sets
