"""Every sprite kind of every game at the counts a user can write (0, 1 and as many as the grid
holds) runs through the env as through the engine alone.

The levels the package makes all hold each kind a few times; the env grows entity tables to at
least two slots, in powers of two, and tables that depend on each other (Solarfox's shots, per
enemy slot) must grow together.
"""

import pytest

from gvgai_pcg.games import get_game, registered_games
from gvgai_pcg.levels import Level, human_level
from tests.envs.level_space import EngineRuns, avatar_cases, base_level, check_env_runs, count_cases

STEPS = 5


def _without(level: Level, chars: str) -> Level:
    return Level(level.game, tuple(row.translate({ord(ch): "." for ch in chars}) for row in level.rows))


@pytest.mark.parametrize("num_envs", [1, 2, 16])
@pytest.mark.parametrize("removed", ["2", "12"])
def test_solarfox_with_fewer_than_two_enemies_runs_in_the_env(removed, num_envs):
    # the shots table, 16 slots per enemy slot of the level, against an enemy table grown to two
    # slots: "shape '[B, 2, 16]' is invalid for input of size 16 B" in reset or step
    level = _without(human_level("solarfox", 0), removed)
    engine = EngineRuns(get_game("solarfox"), 12)
    check_env_runs("solarfox", [level] * num_envs, num_envs, False, 12, engine)


@pytest.mark.slow  # compiling Solarfox's tick costs tens of seconds
def test_solarfox_with_one_enemy_runs_compiled():
    level = _without(human_level("solarfox", 0), "2")
    engine = EngineRuns(get_game("solarfox"), 12)
    check_env_runs("solarfox", [level, level], 2, True, 12, engine)


@pytest.mark.parametrize("game", registered_games())
def test_each_sprite_kind_at_count_0_1_and_its_largest(game):
    base = base_level(game)
    cases = count_cases(base)
    engine = EngineRuns(get_game(game), STEPS)
    # Each in an env of its own: a batch's tables are as wide as its widest level needs.
    few = [level for case in cases for level in (case.zero, case.one)] + avatar_cases(base)
    check_env_runs(game, few, 1, False, STEPS, engine)
    largest = [case.largest for case in cases]
    check_env_runs(game, largest, len(largest), False, 3, EngineRuns(get_game(game), 3), reset_halfway=False)
