"""``gvgai-pcg vgdl list`` and ``inspect``: the parse shown in Java's orders, refusals in one line
(``trace``: test_trace_command.py)."""

from __future__ import annotations

import json

import pytest

from gvgai_pcg.cli import main
from tests.vgdl.test_corpus_games import reset_registry

READY = """BasicGame
    SpriteSet
        floor > Immovable
        hero > MovingAvatar
        rock > Passive
    InteractionSet
        rock hero > attractGaze
        hero EOS > stepBack
        rock wall > stepBack
        hero wall > stepBack
    TerminationSet
        SpriteCounter stype=hero limit=0 win=False
"""
NEEDS = """BasicGame
    SpriteSet
        hero > MovingAvatar
        bomb > Bomber stype=hero
    TerminationSet
        SpriteCounterMore stype=bomb limit=0 win=True
"""


@pytest.fixture
def corpus(tmp_path, monkeypatch):
    (tmp_path / "ready.txt").write_text(READY.replace("attractGaze", "killSprite"))
    (tmp_path / "needs.txt").write_text(NEEDS)
    (tmp_path / "needs_lvl0.txt").write_text("wwww\n")  # a level file, not a game
    monkeypatch.setenv("GVGAI_VGDL_DIR", str(tmp_path))
    reset_registry(monkeypatch)  # corpus games found in this folder, not in one the process met first
    return tmp_path


def test_list_corpus_prints_one_game_a_line_with_what_the_engine_lacks(corpus, capsys):
    assert main(["vgdl", "list", "--corpus"]) == 0
    assert capsys.readouterr().out.splitlines() == ["needs\tneeds Bomber, SpriteCounterMore", "ready\tready"]


def test_list_prints_the_registered_games_whatever_the_corpus(corpus, capsys):
    assert main(["vgdl", "list"]) == 0
    assert capsys.readouterr().out.splitlines() == ["boulderdash", "frogs", "solarfox", "zelda"]


def test_a_registered_name_inspects_the_packages_own_description(corpus, capsys, tmp_path):
    (tmp_path / "zelda.txt").write_text(NEEDS)  # a corpus file of the same name is not the one shown
    assert main(["vgdl", "inspect", "zelda"]) == 0
    out = capsys.readouterr().out
    assert "monsterQuick" in out and "Bomber" not in out


def test_inspect_prints_the_orders_java_uses(tmp_path, capsys):
    path = tmp_path / "game.txt"
    path.write_text(READY)
    assert main(["vgdl", "inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "update order (avatar first, then reverse drawing order): avatar, rock, hero, floor, wall" in out
    assert "EOS (in order, repeats applied again): hero" in out
    assert "   1. rock hero: attractGaze(line 7)\n   2. rock wall: stepBack(line 9)" in out
    assert "  line 12: SpriteCounter stype=hero limit=0 win=False" in out
    assert "not implemented by the engine: attractGaze" in out


def test_inspect_json_is_the_whole_description(corpus, capsys):
    assert main(["vgdl", "inspect", "needs", "--json"]) == 0
    described = json.loads(capsys.readouterr().out)
    assert described["sprite_order"] == ["wall", "hero", "bomb", "avatar"]
    assert described["types"]["bomb"]["java_class"] == "Bomber"


def exit_code(argv: list[str]) -> int:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    return exit_info.value.code


def test_refusals_are_one_line_with_the_file_and_line(tmp_path, capsys, monkeypatch):
    path = tmp_path / "bad.txt"
    path.write_text(READY.replace("Passive", "Pasive"))
    assert exit_code(["vgdl", "inspect", str(path)]) == 2
    assert capsys.readouterr().err == f"gvgai-pcg vgdl: error: {path}:5: unknown sprite class 'Pasive'\n"
    monkeypatch.setenv("GVGAI_VGDL_DIR", str(tmp_path))
    assert exit_code(["vgdl", "inspect", "nosuch"]) == 2
    assert "unknown VGDL game 'nosuch'" in capsys.readouterr().err
    monkeypatch.setenv("GVGAI_VGDL_DIR", str(tmp_path / "absent"))
    assert exit_code(["vgdl", "list", "--corpus"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


PLANNED = """BasicGame
    SpriteSet
        floor > Immovable
        hero > MovingAvatar
        shot > Missile speed=0.5
        nest > SpawnPoint stype=shot
    LevelMapping
        . > floor
        n > floor nest
    InteractionSet
        shot wall > killSprite
        hero shot > killSprite scoreChange=-1
    TerminationSet
        SpriteCounter stype=hero limit=0 win=False
"""


def test_inspect_prints_the_plan_and_a_levels_slots(tmp_path, capsys):
    path, level = tmp_path / "game.txt", tmp_path / "game_lvl0.txt"
    path.write_text(PLANNED)
    level.write_text("wwwww\nwA.nw\nwwwww\n")
    assert main(["vgdl", "inspect", str(path), "--level", str(level)]) == 0
    plan = capsys.readouterr().out.split("\nplan:\n")[1].splitlines()
    assert plan[:2] == [
        "  types: 3 grid, 2 record, 1 table",
        "  rule kinds: 2 P",
    ]  # Java's default avatar too
    assert "  hero: record (the avatar); aligned; 10 px a move" in plan
    assert (
        "  shot: table (Missile moves); off the cells in x and y: a move is 5 px, not whole cells; "
        "5 px a move; slots level shot + cells = 15 (SpawnPoint (line 6) has no bound)"
    ) in plan
    assert "    P hero shot: killSprite(line 12, score -1) on hero x shot: one masked operation" in plan
    assert plan[-1] == "  termination line 14: SpriteCounter counts hero, limit 0 -> lose"


def test_inspect_shows_the_refusal_in_the_plans_place(tmp_path, capsys):
    path = tmp_path / "game.txt"
    path.write_text(READY)
    assert main(["vgdl", "inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.endswith(f"plan: refused: {path}:7: attractGaze is not implemented by the engine yet\n")
    assert main(["vgdl", "inspect", str(path), "--json"]) == 0
    described = json.loads(capsys.readouterr().out)
    assert described["plan"] is None and described["plan_refused"].endswith(
        "attractGaze is not implemented by the engine yet"
    )


def test_inspect_json_holds_the_plan_and_a_bad_level_is_one_line(tmp_path, capsys):
    path = tmp_path / "game.txt"
    path.write_text(PLANNED)
    assert main(["vgdl", "inspect", str(path), "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)["plan"]
    assert plan["types"]["shot"]["representation"] == "table" and plan["slots"] is None
    assert [rule["kind"] for rule in plan["pairs"]] == ["P", "P"]
    (tmp_path / "bad.txt").write_text("wA?w\n")
    assert exit_code(["vgdl", "inspect", str(path), "--level", str(tmp_path / "bad.txt")]) == 2
    assert (
        capsys.readouterr().err
        == "gvgai-pcg vgdl: error: level row 1: character '?' is not in the LevelMapping\n"
    )
    assert exit_code(["vgdl", "inspect", str(path), "--level", str(tmp_path / "absent.txt")]) == 2
    assert "cannot read level" in capsys.readouterr().err
