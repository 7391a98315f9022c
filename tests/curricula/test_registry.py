"""The registry holds the study's regimens, DR and any module of gvgai_pcg.curricula that
defines ``CURRICULUM``; each object answers what the evaluation asks of a run's regimen the way
``gvgai_pcg.evaluation.checkpoints.RunInfo`` does today."""

from __future__ import annotations

from pathlib import Path

import pytest

from gvgai_pcg.config import compose_config
from gvgai_pcg.curricula import registered_curricula
from gvgai_pcg.evaluation.checkpoints import RunInfo

# overrides -> the run's row label and the test sets it trained on (the study's Table 1 names)
EXPECTED = {
    ("regimen=lv", "regimen.level=3"): ("Lv 3", ("lv3",)),
    ("regimen=lv0-3",): ("Lv 0-3", ("lv0", "lv1", "lv2", "lv3")),
    ("regimen=human",): ("Lv 0-4", ("lv0", "lv1", "lv2", "lv3", "lv4")),
    ("regimen=pcg", "regimen.difficulty=0.5"): ("PCG 0.5", ()),
    ("regimen=pcg", "regimen.num_levels=1"): ("PCG 1, 1 level", ("train",)),
    ("regimen=pcg", "regimen.num_levels=100", "regimen.start_seed=7"): ("PCG 1, 100 levels", ("train",)),
    ("regimen=ppcg",): ("PPCG", ()),
    ("regimen=dr",): ("DR", ()),
}


def test_the_study_regimens_come_first_in_their_order():
    assert list(registered_curricula())[:7] == ["lv", "lv0-3", "human", "levels", "pcg", "ppcg", "dr"]


@pytest.mark.parametrize("overrides", list(EXPECTED), ids=" ".join)
def test_a_run_is_labelled_by_its_curriculum(overrides):
    cfg = compose_config(["game=zelda", *overrides])
    config = {"game": {"name": "zelda"}, "regimen": dict(cfg.regimen)}
    run = RunInfo(Path("run"), config, Path("run/model.pt"), 0)
    label, trained_on = EXPECTED[overrides]
    assert (run.label, run.training_sets) == (label, trained_on)
    assert run.has_training_set == (trained_on == ("train",))


def test_a_run_of_a_curriculum_not_installed_here_is_labelled_by_its_name():
    run = RunInfo(Path("run"), {"game": {"name": "zelda"}, "regimen": {"name": "nosuch"}}, Path("m.pt"), 0)
    assert (run.label, run.has_training_set, run.training_sets) == ("nosuch", False, ())


def test_the_names_listed_without_imports_are_the_registered_curricula():
    from gvgai_pcg.curricula.registry import curriculum_names

    # each module of the package defines the curriculum of its own name (plr.py: plr)
    assert set(curriculum_names()) == set(registered_curricula())
