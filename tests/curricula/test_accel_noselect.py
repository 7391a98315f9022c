"""ACCEL without selection (``regimen=accel-noselect``), the control that shows what the editor
alone does: every level offered is kept (the oldest arrival leaves a full buffer), replays are
chosen by staleness only, and it trains and composes as ACCEL does."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.config import compose_config
from gvgai_pcg.config_rules import ConfigError
from gvgai_pcg.curricula import get_curriculum
from gvgai_pcg.curricula.accel_noselect import AccelNoSelect, ArrivalBuffer, UnselectedLevels
from gvgai_pcg.curricula.level_buffer import EDITED_SEED_BASE
from gvgai_pcg.curricula.plr import ReplaySettings
from gvgai_pcg.rl.environment import curriculum_run
from tests.curricula.test_accel import fake_editor, fill  # noqa: F401 (a fixture)
from tests.curricula.test_plr import SMALL, signals


def noselect_source(capacity: int = 3, **settings) -> UnselectedLevels:
    buffer = ArrivalBuffer(capacity, 9, 13, children=8)
    return UnselectedLevels(
        "zelda", buffer, ReplaySettings(**{"rho": 0.0, **settings}), num_edits=5, editor_prob=1.0
    )


def keep_in_order(source: UnselectedLevels, seeds: list[int], scores: list[float]) -> None:
    for seed, score in zip(seeds, scores, strict=True):
        source.observe(signals([dict(env=0, seed=seed, d=0.5, steps=1, finished=True, adv=score)]))


def test_every_level_is_kept_and_the_oldest_arrival_leaves_a_full_buffer(fake_editor):  # noqa: F811
    source = noselect_source(capacity=3)
    keep_in_order(source, [41, 42, 43], [5.0, 0.1, 3.0])
    assert sorted(source.buffer.seed.tolist()) == [41, 42, 43]
    keep_in_order(source, [44], [0.0])  # below every score: ACCEL would not keep it
    assert sorted(source.buffer.seed.tolist()) == [42, 43, 44]  # 41 arrived first, and left
    keep_in_order(source, [45], [0.0])
    assert sorted(source.buffer.seed.tolist()) == [43, 44, 45]


def test_a_child_below_every_score_is_kept(fake_editor):  # noqa: F811
    source = noselect_source(capacity=3, replay_prob=1.0)
    fill(source, 3)
    source.observe(signals([dict(env=0, seed=21, d=0.2, steps=2, finished=True, adv=1.5)]))  # a replay
    (child,) = source.next_levels(torch.arange(1), torch.tensor([5]), torch.zeros(1))
    assert child.seed == EDITED_SEED_BASE
    source.observe(signals([dict(env=0, seed=EDITED_SEED_BASE, d=0.2, steps=2, finished=True, adv=-9.0)]))
    assert EDITED_SEED_BASE in source.buffer.seed.tolist()


def test_replays_ignore_the_score():
    buffer = ArrivalBuffer(3, 9, 13)
    buffer.valid[:] = True
    buffer.score[:] = torch.tensor([100.0, 0.0, -5.0])
    buffer.last_sampled[:] = torch.tensor([0, 0, 0])
    buffer.clock[0] = 10
    probabilities = buffer.replay_probabilities(temperature=0.3, staleness_coef=0.3)
    assert torch.allclose(probabilities, torch.full((3,), 1 / 3, dtype=torch.float64))


def test_it_is_registered_and_composes_with_accels_settings_and_staleness_only():
    assert isinstance(get_curriculum("accel-noselect"), AccelNoSelect)
    cfg = compose_config(["condition=zelda-accel-noselect"])
    assert cfg.run_name == "zelda-accel-noselect-tiles-compact-seed0"
    accel = compose_config(["game=zelda", "regimen=accel"]).regimen
    for key in ("buffer_size", "score", "replay_prob", "rho", "num_edits", "editor_prob", "robust"):
        assert cfg.regimen[key] == accel[key], key
    assert cfg.regimen.staleness_coef == 1.0
    assert isinstance(curriculum_run(cfg.regimen, "zelda").state, ArrivalBuffer)
    with pytest.raises(ConfigError, match="accel-noselect replays by staleness only"):
        compose_config(["condition=zelda-accel-noselect", "regimen.staleness_coef=0.3"])


def test_it_trains_through_the_command_line(fake_editor, tmp_path):  # noqa: F811
    from gvgai_pcg.commands.train import run_raw

    run = [
        *SMALL,
        "regimen=accel-noselect",
        "regimen.buffer_size=8",
        "regimen.rho=0.1",
        f"out_dir={tmp_path}",
    ]
    assert run_raw([*run, "total_frames=200"]) == 0
    saved = torch.load(
        tmp_path / "zelda-accel-noselect-tiles-compact-seed0" / "checkpoints" / "last.pt", weights_only=False
    )["curriculum"]
    assert int(saved["children_made"][0]) > 0 and int(saved["arrivals"][0]) > 0
