"""Any level a user can write runs through the env as through the engine alone: a property test
over the space of valid levels, drawn for each registered game from its level format alone (so a
game registered later is covered as it is), and every level the format refuses is refused when
the env is made, in one line.

Each level is played in envs batched 1, 2 and 16 to a batch (levels mixed in a batch), eager and
compiled, with a partial reset halfway; every env at every step equals the engine alone on that
level by itself (``tests/envs/level_space.py``), so the batchings and modes equal each other too.
``make test`` runs a modest draw eagerly (compiling a game's tick costs tens of seconds); the
slow-marked long run draws many more and runs them compiled as well.
"""

import random
from functools import partial

import pytest

from gvgai_pcg.envs import GVGAIEnv, LevelPerEnv
from gvgai_pcg.games import get_game, registered_games, study_games
from gvgai_pcg.levels import Level, LevelFormatError, level_format
from tests.envs.level_space import EngineRuns, check_env_runs, random_level, wall_char


def draw_levels(game: str, count: int, seed: int) -> list[Level]:
    rng = random.Random(f"{game} {seed}")
    return [random_level(level_format(game), rng, name=f"{game} draw {seed}.{i}") for i in range(count)]


def run_levels(game: str, levels: list[Level], steps: int, modes: tuple[bool, ...]) -> None:
    """``levels`` through envs of 16, 2 and 1 (the first 16, 4 and 2 of them for the smaller
    batchings, all of them in the long run), eager and compiled as ``modes`` say."""
    engine = EngineRuns(get_game(game), steps)
    for compiled in modes:
        check_env_runs(game, levels, 16, compiled, steps, engine)
        check_env_runs(game, levels[: max(4, len(levels) // 4)], 2, compiled, steps, engine)
        check_env_runs(game, levels[: max(2, len(levels) // 16)], 1, compiled, steps, engine)


@pytest.mark.parametrize("game", registered_games())
def test_valid_levels_run_through_the_env_as_through_the_engine(game):
    run_levels(game, draw_levels(game, 16, seed=0), steps=6, modes=(False,))


@pytest.mark.slow
@pytest.mark.parametrize("game", registered_games())
def test_many_valid_levels_run_through_the_env_as_through_the_engine_eager_and_compiled(game):
    # 128 levels a game, 20 steps, eager and compiled (compiling the tick for every table width
    # met): minutes a game
    run_levels(game, draw_levels(game, 128, seed=1), steps=20, modes=(False, True))


def test_the_drawn_levels_cover_the_format():
    # sizes from one cell to the full grid, every character absent and flooding, walled borders
    # (the study games' formats; a corpus game's 15 characters flood a third of the grid rarely)
    for game in study_games():
        fmt, levels = level_format(game), draw_levels(game, 256, seed=0)
        assert all(level.check() is level for level in levels)
        sizes = {(level.height, level.width) for level in levels}
        assert (fmt.height, fmt.width) in sizes
        assert min(h for h, _ in sizes) == 1 and min(w for _, w in sizes) == 1
        for ch in fmt.chars:
            if ch not in fmt.avatar_chars:
                counts = [level.count(ch) for level in levels]
                assert min(counts) == 0 and max(counts) >= fmt.height * fmt.width // 3, (game, ch)
        walled = [level for level in levels if level.height > 2 and level.width > 2]
        border = wall_char(fmt) + fmt.avatar_chars
        assert any(all(ch in border for ch in level.rows[0] + level.rows[-1]) for level in walled)
        assert any(not all(ch in border for ch in level.rows[0]) for level in walled)


def _refused(game: str) -> dict[str, tuple[str, ...]]:
    """Levels ``game``'s format refuses, by what is wrong with them, and what the error says."""
    fmt = level_format(game)
    avatar, other = fmt.avatar_chars[0], next(ch for ch in fmt.chars if ch not in fmt.avatar_chars)
    return {
        "no avatar": ((other * 3,) * 2, "no avatar"),
        "two avatars": ((avatar * 2,), "a second avatar"),
        "a character outside the legend": ((avatar + "~",), "not in the"),
        "padding": ((avatar + " ",), "not in the"),
        "ragged rows": ((avatar + other, other), "ragged rows"),
        "too wide": ((avatar + other * fmt.width,), "at most"),
        "too high": ((avatar,) + (other,) * fmt.height, "at most"),
        "no rows": ((), "empty level"),
        "an empty row": (("",), "empty level"),
    }


@pytest.mark.parametrize("game", registered_games())
def test_a_level_the_format_refuses_is_refused_in_one_line_when_the_env_is_made(game):
    for what, (rows, says) in _refused(game).items():
        level = Level(game, rows, name=f"my {what} level")
        makes = {
            "an env of it": partial(GVGAIEnv, game, 2, level),
            "an env of a list": partial(GVGAIEnv, game, 2, [level, level]),
            "a source of it": partial(LevelPerEnv, [level]),
            "the level's check": level.check,
        }
        for make, refuse in makes.items():
            with pytest.raises(LevelFormatError, match=says) as refused:
                refuse()
            assert f"my {what} level" in str(refused.value) and "\n" not in str(refused.value), (what, make)
