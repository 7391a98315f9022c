"""The Hydra configs: groups, the paper preset, one directory per run of a sweep."""

from __future__ import annotations

import itertools

import pytest


def test_the_paper_preset_sets_the_study_settings(make_config):
    cfg = make_config(["preset=paper"])
    assert cfg.model.name == "nature" and cfg.model.hidden == 512
    assert (cfg.env.obs, cfg.env.num_envs, cfg.env.max_steps) == ("pixels", 12, 2000)
    assert cfg.algo.lr == 7e-4 and cfg.algo.n_steps == 5 and cfg.algo.gamma == 0.99
    assert (cfg.algo.entropy_coef, cfg.algo.value_coef, cfg.algo.max_grad_norm) == (0.01, 0.5, 0.5)
    assert (cfg.algo.rmsprop_alpha, cfg.algo.rmsprop_eps) == (0.99, 1e-5)
    assert cfg.regimen.win_rule == "study" and cfg.total_frames == 40_000_000
    assert cfg.log.every_episodes == 12


@pytest.mark.parametrize(
    "overrides, tag",
    [
        (["regimen=lv", "regimen.level=3"], "lv3"),
        (["regimen=lv0-3"], "lv0-3"),
        (["regimen=pcg", "regimen.difficulty=0.3"], "pcg0.3"),
        (["regimen=ppcg"], "ppcg"),
    ],
)
def test_regimens(make_config, overrides, tag):
    assert make_config(overrides).regimen.tag == tag


def test_every_run_of_a_sweep_has_its_own_directory(make_config):
    # gvgai-pcg train -m game=zelda,frogs regimen=ppcg,pcg seed=0,1,2,3
    configs = {regimen: make_config([f"regimen={regimen}"]) for regimen in ("ppcg", "pcg")}
    names = set()
    for game, regimen, seed in itertools.product(["zelda", "frogs"], ["ppcg", "pcg"], range(4)):
        cfg = configs[regimen]
        cfg.game.name, cfg.seed = game, seed
        names.add(cfg.run_name)
    assert len(names) == 16
