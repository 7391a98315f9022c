"""The games' level editors (ACCEL, issue 36): small, seeded edits that keep a level valid for its
format and checks, that every edit kind happens, and that the env plays the edited levels."""

from __future__ import annotations

import importlib
from collections import Counter
from functools import cache

import pytest
import torch

from gvgai_pcg.games import registry
from gvgai_pcg.games.editing import ATTEMPTS, apply_edit
from gvgai_pcg.generators import generate_level
from gvgai_pcg.generators.validation import playability_problems
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.human import human_level
from gvgai_pcg.levels.winnable import missing_to_win
from tests.games import toy_game

GAMES = ("zelda", "solarfox", "frogs", "boulderdash")
EDITS = 200
MAX_CHANGED_CELLS = 4


def editor_module(game: str):
    return importlib.import_module(f"gvgai_pcg.games.{game}.editor")


@cache
def parents(game: str) -> tuple[Level, ...]:
    """Generated levels at d = 0, 0.5 and 1, and the human levels."""
    generated = [generate_level(game, d, seed) for d in (0.0, 0.5, 1.0) for seed in range(12)]
    return (*generated, *(human_level(game, i) for i in range(5)))


@cache
def edits(game: str) -> tuple[tuple[Level, str | None, Level], ...]:
    """(parent, kind, child) for ``EDITS`` seeded edits spread over ``parents(game)``."""
    levels = parents(game)
    kinds = editor_module(game).KINDS
    return tuple(
        (levels[seed % len(levels)], *apply_edit(levels[seed % len(levels)], seed, kinds, game))
        for seed in range(EDITS)
    )


def changed_cells(parent: Level, child: Level) -> list[tuple[int, int]]:
    return [
        (r, c)
        for r, (a, b) in enumerate(zip(parent.rows, child.rows, strict=True))
        for c, (x, y) in enumerate(zip(a, b, strict=True))
        if x != y
    ]


@pytest.mark.parametrize("game", GAMES)
def test_every_game_of_the_study_registers_its_editor(game):
    assert registry.level_editor(game) is editor_module(game).edit


@pytest.mark.parametrize("game", GAMES)
def test_edits_keep_levels_valid_and_small(game):
    unchanged = 0
    for parent, kind, child in edits(game):
        assert (child.game, child.height, child.width) == (parent.game, parent.height, parent.width)
        assert (child.name, child.seed) == (None, None)
        assert Level.parse(str(child), game) == child  # legal characters, one avatar
        assert missing_to_win(child) == []
        assert set(playability_problems(child)) <= set(playability_problems(parent))
        if parent.seed is not None:  # a generated level: it had no problem, nor has its edit
            assert playability_problems(child) == []
        changed = changed_cells(parent, child)
        assert len(changed) <= MAX_CHANGED_CELLS, (kind, str(parent), str(child))
        if kind is None:
            unchanged += 1
            assert child == parent
        else:
            assert changed
    assert unchanged <= EDITS // 50  # only where no edit fits (a Frogs level of grass lanes, say)


@pytest.mark.parametrize("game", GAMES)
def test_every_edit_kind_happens(game):
    happened = Counter(kind for _, kind, _ in edits(game))
    assert set(editor_module(game).KINDS) <= set(happened), happened


@pytest.mark.parametrize("game", ["zelda", "solarfox", "boulderdash"])
def test_edits_keep_off_the_border(game):
    """Changed cells lie inside the box of the cells that are not wall: the outer walls (and the
    generators' frame) stay. Frogs' frame is held by its checks (wall lines, walled goal)."""
    for parent, _, child in edits(game):
        open_cells = [(r, c) for r, row in enumerate(parent.rows) for c, ch in enumerate(row) if ch != "w"]
        rows, cols = [r for r, _ in open_cells], [c for _, c in open_cells]
        for r, c in changed_cells(parent, child):
            assert min(rows) <= r <= max(rows) and min(cols) <= c <= max(cols)
            assert 0 < c < parent.width - 1
            assert 0 < r < parent.height - 1 or game == "solarfox"  # its enemies move in rows 0 and -1


def test_frogs_edits_keep_each_lane_its_kind():
    for parent, kind, child in edits("frogs"):
        for r, c in changed_cells(parent, child):
            before, after = parent.rows[r][c], child.rows[r][c]
            if kind in ("add_log", "remove_log"):
                assert {before, after} == {"0", "="}
            elif kind in ("add_vehicle", "remove_vehicle"):
                assert "." in (before, after) and set(child.rows[r]) <= set(".-x_lw")
                directions = {("x-" if ch in "x-" else "l_") for ch in child.rows[r] if ch in "x-l_"}
                assert len(directions) <= 1 or set(parent.rows[r]) >= set(child.rows[r]) - {"."}
            else:
                assert kind == "move_goal" and set(before + after) <= set("wg+")


def test_the_same_seed_gives_the_same_edit_and_seeds_differ():
    for game in GAMES:
        edit = registry.level_editor(game)
        for level in (generate_level(game, 0.5, 3), human_level(game, 1)):
            assert edit(level, 7) == edit(level, 7)
            children = [edit(level, seed) for seed in range(41)]
            assert (
                sum(a != b for a, b in zip(children[:-1], children[1:], strict=True)) >= 32
            )  # 80 % of neighbours differ
            assert len(set(children)) >= 15


def test_the_last_of_what_the_win_needs_is_never_removed():
    """A Solarfox level with one pill and nowhere else to edit comes back unchanged."""
    rows = ["ww2wwwwwww"] + ["w" * 10] * 4 + ["wwwwAbwwww"] + ["w" * 10] * 4 + ["ww1wwwwwww"]
    level = Level.parse("\n".join(rows), "solarfox", name="one_pill")
    kinds = editor_module("solarfox").KINDS
    for seed in range(20):
        kind, child = apply_edit(level, seed, kinds, "solarfox")
        assert kind is None and child == level and child.name is None
    # Boulderdash: nine diamonds are needed; an edit never leaves fewer.
    nine = generate_level("boulderdash", 1.0, 0)
    gems = nine.find("x")
    rows = [list(row) for row in nine.rows]
    for r, c in gems[9:]:
        rows[r][c] = "."
    nine = Level("boulderdash", tuple("".join(row) for row in rows))
    assert nine.count("x") == 9
    assert all(registry.level_editor("boulderdash")(nine, seed).count("x") >= 9 for seed in range(60))


def test_an_editor_refuses_another_games_level():
    with pytest.raises(ValueError, match="the zelda editor was given a frogs level"):
        registry.level_editor("zelda")(human_level("frogs", 0), 0)


def test_a_game_without_an_editor_is_named_in_one_line():
    with pytest.raises(
        ValueError, match="no level editor for game 'nosuchgame'; games with an editor are: "
    ) as e:
        registry.level_editor("nosuchgame")
    assert "\n" not in str(e.value) and "boulderdash, frogs, solarfox, zelda" in str(e.value)


def test_the_toy_game_has_no_editor_and_is_refused_by_name():
    tables = (registry._SPECS, registry._GAMES, registry._RULES, registry._GENERATORS)
    saved = [dict(table) for table in tables]
    try:
        registry.register_game_spec(toy_game.SPEC)
        with pytest.raises(ValueError, match="no level editor for game 'toy'; games with an editor are: b"):
            registry.level_editor("toy")
    finally:
        for table, before in zip(tables, saved, strict=True):
            table.clear()
            table.update(before)


def test_editing_tries_a_bounded_number_of_draws():
    calls = []

    def never(grid, rng):
        calls.append(1)
        return False

    level = human_level("zelda", 0)
    assert apply_edit(level, 0, {"never": never}, "zelda") == (None, level)
    assert len(calls) == ATTEMPTS


@pytest.mark.parametrize("game", GAMES)
def test_the_env_plays_edited_levels(game, monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    from gvgai_pcg.envs import GVGAIEnv

    edited = [child for _, kind, child in edits(game)[:40] if kind is not None][:8]
    env = GVGAIEnv(game, 4, levels=edited, max_steps=50, seed=3, compile_tick=False)
    out = env.reset()
    assert all(level in edited for level in env.current_levels)
    for _ in range(5):
        out = env.step_and_maybe_reset(out.set("action", torch.zeros(4, dtype=torch.int64)))[1]
    assert out["tiles"].shape[0] == 4 and out["tiles"].shape[-2:] == (edited[0].height, edited[0].width)
    assert bool(torch.isfinite(out["score"].float()).all())
    assert all(level in edited for level in env.current_levels)
    env.close()


def test_frogs_checks_read_a_frog_that_starts_on_a_log():
    """Human level 4 starts the frog on a log (B): its checks name the start row, not crash."""
    assert playability_problems(human_level("frogs", 4)) == ["the start row is not grass"]


def _hand_built(game: str) -> dict[str, Level]:
    """``Level`` objects built by hand that are not levels of ``game``."""
    good = human_level(game, 0)
    return {
        "no rows": Level(game, ()),
        "ragged": Level(game, (*good.rows[:-1], good.rows[-1][:-3])),
        "an unknown character": Level(game, (good.rows[0][:-1] + "?", *good.rows[1:])),
        "no avatar": Level(game, tuple("w" * len(row) for row in good.rows)),
    }


@pytest.mark.parametrize("game", GAMES)
def test_a_hand_built_invalid_level_is_refused_in_one_line_naming_what_is_wrong(game):
    edit = registry.level_editor(game)
    says = {"no rows": "empty level", "ragged": "ragged rows", "an unknown character": "'?'"}
    for case, level in _hand_built(game).items():
        with pytest.raises(ValueError) as error:
            edit(level, 0)
        text = str(error.value)
        assert text.startswith(f"the {game} editor was given a level that is not a valid {game} level: ")
        assert says.get(case, "no avatar") in text and "\n" not in text, (case, text)
