"""Over 200 seeds per (game, d), the generated levels follow GENERATORS.md §1.2-1.7: counts and
sizes within the documented ranges and, where a formula gives one, means within a few standard
errors of the formula's mean (tests/generators/formulas.py). Tolerances are tight enough that a
wrong constant in a formula fails."""

from __future__ import annotations

import numpy as np
import pytest
from generator_formulas import (
    boulderdash_counts,
    frogs_first_lane,
    frogs_size,
    solarfox_pill_target,
    zelda_enemies,
    zelda_walls_removed,
)
from generator_samples import DIFFICULTIES, GAMES, sample

from gvgai_pcg.generators import generate_level
from gvgai_pcg.generators._common import difficulty_tag
from gvgai_pcg.generators.counts import level_counts
from gvgai_pcg.generators.validation import playability_problems
from gvgai_pcg.levels.level import Level


def counts(game: str, d: float, key: str) -> np.ndarray:
    return np.array([level_counts(level)[key] for level in sample(game, d)])


def assert_mean(values: np.ndarray, expected: float, sigmas: float = 4.0, floor: float = 0.05) -> None:
    """Mean of ``values`` within ``sigmas`` standard errors (at least ``floor``) of ``expected``."""
    tolerance = max(sigmas * values.std() / np.sqrt(len(values)), floor)
    assert abs(values.mean() - expected) <= tolerance, (values.mean(), expected, tolerance)


@pytest.mark.parametrize("game", GAMES)
@pytest.mark.parametrize("d", DIFFICULTIES)
def test_every_level_parses_validates_and_is_named(game, d):
    fmt_levels = sample(game, d)
    for seed, level in enumerate(fmt_levels):
        parsed = Level.parse(str(level), game)
        assert parsed == level and (parsed.width, parsed.height) == (level.format.width, level.format.height)
        assert playability_problems(level) == [], (seed, str(level))
        assert level.seed == seed and level.name == f"{game}_d{difficulty_tag(d)}_s{seed}"


@pytest.mark.parametrize("game", GAMES)
@pytest.mark.parametrize("d", DIFFICULTIES)
def test_same_seed_same_level(game, d):
    for seed in (0, 7, 123456789):
        assert generate_level(game, d, seed).rows == generate_level(game, d, seed).rows
    assert len({sample(game, d)[s].rows for s in range(50)}) > 40


# Zelda (§1.2): 0-1 / 1-2 / 2-3 enemies; interior walls ~2-9 at d <= 0.5, 11-21 at d = 1.
@pytest.mark.parametrize("d, low, high", [(0.0, 0, 1), (0.5, 1, 2), (1.0, 2, 3)])
def test_zelda_enemies(d, low, high):
    enemies = counts("zelda", d, "enemies")
    assert low <= enemies.min() and enemies.max() <= high
    assert_mean(enemies, zelda_enemies(d).mean())


def test_zelda_walls():
    for d in (0.0, 0.5):
        walls = counts("zelda", d, "interior_walls")
        assert np.mean((walls >= 2) & (walls <= 9)) >= 0.9
        assert 4.0 <= walls.mean() <= 6.5  # nearly every removable wall removed
    walls = counts("zelda", 1.0, "interior_walls")
    assert 11 <= walls.min() and walls.max() <= 21
    # 30 interior walls in a 6x4 perfect maze; at d = 1 fewer than the removable ones are removed
    assert_mean(walls, 30 - zelda_walls_removed(1.0).mean(), floor=0.3)


def test_zelda_door_and_key_move_away_with_d():
    def mean_distance(d: float, char: str) -> float:
        distances = []
        for level in sample("zelda", d):
            (ar, ac), (tr, tc) = level.find("A")[0], level.find(char)[0]
            distances.append(abs(ar - tr) + abs(ac - tc))
        return float(np.mean(distances))

    assert mean_distance(1.0, "g") > mean_distance(0.0, "g") + 0.3
    assert mean_distance(0.0, "g") > 9  # far from the avatar even at d = 0 (mean tile distance ~6.5)


# Solarfox (§1.3): `.` always 14, `w` always 22; placements 5-10 / 25-30 / 45-50 (mirrored, so
# the final pill count is below the target); margins keep pills central at d = 0; offsets 3/2/2.
@pytest.mark.parametrize("d, low, high", [(0.0, 5, 7.5), (0.5, 17, 21.5), (1.0, 31, 36.5)])
def test_solarfox_pills(d, low, high):
    pills = counts("solarfox", d, "pills")
    target = solarfox_pill_target(d)
    assert pills.min() >= 1 and pills.max() <= 4 * np.ceil(target.max() / 4)
    assert low <= pills.mean() <= high
    assert counts("solarfox", d, "enemy_ground").tolist() == [14] * 200
    assert counts("solarfox", d, "walls").tolist() == [22] * 200


def test_solarfox_pills_central_at_d0():
    for level in sample("solarfox", 0.0):
        for r, c in level.find("b") + level.find("p"):
            assert 3 <= c <= 6 and 3 <= r <= 7, str(level)


@pytest.mark.parametrize("d, offsets", [(0.0, {0, 3}), (0.5, {0, 2}), (1.0, {0, 2})])
def test_solarfox_enemy_offsets(d, offsets):
    seen = set()
    for level in sample("solarfox", d):
        seen.add(abs(level.rows[0].index("2") - 5))
        seen.add(abs(level.rows[-1].index("1") - 5))
    assert seen == offsets


# Frogs (§1.4): widths 8-10 / 16-19 / 25-27, rows 4-6 / 5-7 / 6-8 (+2); lane weights.
@pytest.mark.parametrize(
    "d, widths, heights", [(0.0, (8, 10), (6, 8)), (0.5, (16, 19), (7, 9)), (1.0, (25, 27), (8, 10))]
)
def test_frogs_active_size(d, widths, heights):
    width, height = counts("frogs", d, "width"), counts("frogs", d, "height")
    assert widths[0] <= width.min() and width.max() <= widths[1]
    assert heights[0] <= height.min() and height.max() <= heights[1]
    expected_width, expected_height = frogs_size(d)
    assert_mean(width, expected_width.mean())
    assert_mean(height, expected_height.mean())


@pytest.mark.parametrize("d", DIFFICULTIES)
def test_frogs_first_lane_types(d):
    """Row 1 under the goal row always gets its own draw: its type follows the lane weights."""
    kinds = []
    for level in sample("frogs", d):
        rows = [row for row in level.rows if set(row) != {"w"}]
        lane = set(rows[1])
        kinds.append(0 if lane & set(".lx_-") else 1 if lane & set("0=13") else 2)
    observed = np.bincount(kinds, minlength=3) / len(kinds)
    assert np.all(np.abs(observed - frogs_first_lane(d)) <= 0.1), (observed, frogs_first_lane(d))


def test_frogs_lanes_by_difficulty():
    assert counts("frogs", 0.0, "street_lanes").sum() == counts("frogs", 0.0, "water_lanes").sum() == 0
    assert counts("frogs", 1.0, "water_lanes").mean() > 1.5 * counts("frogs", 1.0, "street_lanes").mean()
    # at d = 1 grass lanes exist only as the separator after a multi-row run (the loop quirk)
    for level in sample("frogs", 1.0):
        rows = [row for row in level.rows if set(row) != {"w"}]
        for i in range(2, len(rows) - 1):
            if "+" in rows[i]:
                assert "+" not in rows[i - 1], str(level)


def test_frogs_water_lanes_end_in_spawners():
    for level in sample("frogs", 1.0):
        rows = [row.strip("w") for row in level.rows if set(row) & set("0=")]
        for row in rows:
            assert row[-1] in "13" and row[-2] in "=13", row


# Boulderdash (§1.5): gems 14-16 / 13-17 / 11-14 (target 10 + E), boulders 0 / 7-10 / 14-20 (from
# the raw extra-gem fraction), enemies 0 / 2-5 / 9-15.
@pytest.mark.parametrize(
    "d, gems, boulders, enemies",
    [(0.0, (14, 16), (0, 0), (0, 0)), (0.5, (13, 17), (7, 10), (2, 5)), (1.0, (11, 14), (14, 20), (9, 15))],
)
def test_boulderdash_counts(d, gems, boulders, enemies):
    expected = boulderdash_counts(d)
    for key, (low, high) in (("gems", gems), ("boulders", boulders), ("enemies", enemies)):
        values = counts("boulderdash", d, key)
        assert low <= values.min() and values.max() <= high, key
        assert_mean(values, expected[key].mean())


def test_boulderdash_boulders_use_raw_gem_fraction():
    """B = floor((0.7+0.3r) d 2 (10 + g)) reaches 20 at d = 1; with E instead of g it could not
    exceed floor(2 (10 + 4)) = 28 and its mean would sit near 26, not 17."""
    boulders = counts("boulderdash", 1.0, "boulders")
    assert boulders.max() <= 20 and 16 <= boulders.mean() <= 18
