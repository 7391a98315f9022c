"""ACCEL (``regimen=accel``): levels stored by content, children made from the very levels just
replayed, played next, and kept by score; trained through the real trainer. The game's editor
(``gvgai_pcg.games.registry.level_editor``) is replaced by a fake that walls one floor cell."""

from __future__ import annotations

import pytest
import torch

import gvgai_pcg.games.registry as games_registry
from gvgai_pcg.config import compose_config
from gvgai_pcg.curricula.accel import EditedLevelBuffer, EditedLevels, decode_level, encode_level
from gvgai_pcg.curricula.level_buffer import EDITED_SEED_BASE
from gvgai_pcg.curricula.plr import ReplaySettings
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels import Level
from gvgai_pcg.rl.environment import curriculum_run
from tests.curricula.test_plr import SMALL, signals


def wall_one_floor_cell(level: Level, seed: int) -> Level:
    """The fake editor: the ``seed``-th floor cell (cyclically) becomes a wall."""
    cells = [(r, c) for r, row in enumerate(level.rows) for c, ch in enumerate(row) if ch == "."]
    r, c = cells[seed % len(cells)]
    rows = list(level.rows)
    rows[r] = rows[r][:c] + "w" + rows[r][c + 1 :]
    return Level(level.game, rows, seed=level.seed)


@pytest.fixture
def fake_editor(monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    asked = []

    def level_editor(game):
        asked.append(game)
        return wall_one_floor_cell

    monkeypatch.setattr(games_registry, "level_editor", level_editor, raising=False)
    return asked


def test_levels_are_stored_by_content():
    level = generate_level("zelda", 0.4, 12)
    codes = encode_level(level, 10, 14)  # larger than the level: padded
    assert codes.dtype == torch.uint8 and codes[9].eq(0).all() and codes[:, 13].eq(0).all()
    assert decode_level("zelda", codes, 99) == level and decode_level("zelda", codes, 99).seed == 99
    with pytest.raises(ValueError, match="does not fit 8x13"):
        encode_level(level, 8, 13)


def accel_source(capacity: int = 4, **settings) -> EditedLevels:
    buffer = EditedLevelBuffer(capacity, 9, 13, children=8)
    return EditedLevels(
        "zelda", buffer, ReplaySettings(**{"rho": 0.0, **settings}), num_edits=5, editor_prob=1.0
    )


def fill(source: EditedLevels, count: int) -> list[Level]:
    ds = [0.1, 0.2, 0.3, 0.4][:count]
    levels = [generate_level("zelda", d, 20 + i) for i, d in enumerate(ds)]
    for i, (level, d) in enumerate(zip(levels, ds, strict=True)):
        source.buffer.insert(level.seed, d, 0.5 + i, 0.0, encode_level(level, 9, 13))
    return levels


def test_the_children_are_edits_of_the_level_just_replayed(fake_editor):
    source = accel_source()
    parents = fill(source, 3)
    played = parents[1]  # env 2 replayed the second level; the others were not played
    source.observe(signals([dict(env=2, seed=played.seed, d=0.2, steps=3, finished=True, adv=0.1)]))
    assert fake_editor == ["zelda"] and int(source.buffer.children_made[0]) == 1
    expected = played
    for j in range(5):
        expected = wall_one_floor_cell(expected, j)
    child = decode_level("zelda", source.buffer.child_content[0], EDITED_SEED_BASE)
    assert child == expected and child != played  # five edits of the replayed level itself
    assert all(child != wall_one_floor_cell(other, 0) for other in (parents[0], parents[2]))
    assert float(source.buffer.child_d[0]) == 0.2 and int(source.buffer.child_seed[0]) == EDITED_SEED_BASE
    # a new level's episode makes no child
    source.observe(signals([dict(env=0, seed=7, d=0.9, steps=3, finished=True, adv=0.0)]))
    assert int(source.buffer.children_made[0]) == 1


def test_a_child_plays_next_with_its_own_seed_and_joins_the_buffer_by_score(fake_editor):
    source = accel_source(capacity=3, replay_prob=1.0)
    fill(source, 3)  # full: scores 0.5, 1.5, 2.5
    source.observe(signals([dict(env=0, seed=21, d=0.2, steps=2, finished=True, adv=1.5)]))
    source.observe(signals([dict(env=0, seed=22, d=0.3, steps=2, finished=True, adv=2.5)]))
    first, second = source.next_levels(torch.arange(2), torch.tensor([5, 6]), torch.zeros(2))
    assert (first.seed, second.seed) == (EDITED_SEED_BASE, EDITED_SEED_BASE + 1)  # oldest first
    assert source.level_difficulties(torch.arange(2), torch.tensor([5, 6]), torch.zeros(2)).tolist() == [
        0.2,
        0.3,
    ]
    rows = [
        dict(env=0, seed=EDITED_SEED_BASE, d=0.2, steps=2, finished=True, adv=9.0),  # beats 0.5
        dict(env=1, seed=EDITED_SEED_BASE + 1, d=0.3, steps=2, finished=True, adv=0.1),  # below all
    ]
    source.observe(signals(rows))
    index = int(
        source.buffer.find(torch.tensor([EDITED_SEED_BASE]), torch.tensor([0.2], dtype=torch.float64))
    )
    assert index == 0 and float(source.buffer.score[0]) == 9.0  # in place of the lowest
    assert decode_level("zelda", source.buffer.content[0], 0) == decode_level(
        "zelda", source.buffer.child_content[0], 0
    )
    assert source.buffer.find(
        torch.tensor([EDITED_SEED_BASE + 1]), torch.tensor([0.3], dtype=torch.float64)
    ).tolist() == [-1]
    replayed = source.next_levels(torch.arange(1), torch.tensor([8]), torch.zeros(1))[0]
    assert replayed.seed in source.buffer.seed.tolist()  # no child waits: a replay, by content


def test_new_generated_levels_join_by_content(fake_editor):
    source = accel_source()
    source.observe(signals([dict(env=0, seed=31, d=0.5, steps=2, finished=True, adv=0.3)]))
    assert decode_level("zelda", source.buffer.content[0], 31) == generate_level("zelda", 0.5, 31)


def test_a_game_without_an_editor_is_named(monkeypatch):
    monkeypatch.delattr(games_registry, "level_editor", raising=False)
    source = accel_source()
    fill(source, 1)
    with pytest.raises(ValueError, match="regimen accel needs a level editor for 'zelda'"):
        source.observe(signals([dict(env=0, seed=20, d=0.1, steps=1, finished=True, adv=0.1)]))


def test_regimen_accel_composes_with_dcds_defaults():
    cfg = compose_config(["game=zelda", "regimen=accel"])
    assert cfg.run_name == "zelda-accel-tiles-compact-seed0"
    assert (cfg.regimen.num_edits, cfg.regimen.editor_prob, cfg.regimen.replay_prob) == (5, 1.0, 0.8)
    buffer = curriculum_run(cfg.regimen, "zelda").state
    assert isinstance(buffer, EditedLevelBuffer) and buffer.content.shape == (4000, 9, 13)


def test_it_trains_through_the_command_line_and_makes_children(fake_editor, tmp_path):
    from gvgai_pcg.commands.train import run_raw

    run = [*SMALL, "regimen=accel", "regimen.buffer_size=16", "regimen.rho=0.1", f"out_dir={tmp_path}"]
    assert run_raw([*run, "total_frames=200"]) == 0
    saved = torch.load(
        tmp_path / "zelda-accel-tiles-compact-seed0" / "checkpoints" / "last.pt", weights_only=False
    )["curriculum"]
    assert int(saved["children_made"][0]) > 0 and bool(saved["valid"].any())
    assert saved["content"][saved["valid"]].ne(0).any(dim=(1, 2)).all()  # every level kept by content


def test_the_games_own_editor_makes_the_children(monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    source = accel_source()
    parent = fill(source, 1)[0]
    child = source.child_of(parent, EDITED_SEED_BASE + 3)
    assert isinstance(child, Level) and child.game == "zelda" and child != parent
    assert child == source.child_of(parent, EDITED_SEED_BASE + 3)  # the edits follow the seed
