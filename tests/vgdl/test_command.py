"""``gvgai-pcg vgdl list`` and ``inspect``: the parse shown in Java's orders, refusals in one line."""

from __future__ import annotations

import json

import pytest

from gvgai_pcg.cli import main

READY = """BasicGame
    SpriteSet
        floor > Immovable
        hero > MovingAvatar
        rock > Passive
    InteractionSet
        rock hero > bounceForward
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
        Timeout limit=10 win=True
"""


@pytest.fixture
def corpus(tmp_path, monkeypatch):
    (tmp_path / "ready.txt").write_text(READY.replace("bounceForward", "killSprite"))
    (tmp_path / "needs.txt").write_text(NEEDS)
    (tmp_path / "needs_lvl0.txt").write_text("wwww\n")  # a level file, not a game
    monkeypatch.setenv("GVGAI_VGDL_DIR", str(tmp_path))
    return tmp_path


def test_list_prints_one_game_a_line_with_what_the_engine_lacks(corpus, capsys):
    assert main(["vgdl", "list"]) == 0
    assert capsys.readouterr().out.splitlines() == ["needs\tneeds Bomber, Timeout", "ready\tready"]


def test_inspect_prints_the_orders_java_uses(tmp_path, capsys):
    path = tmp_path / "game.txt"
    path.write_text(READY)
    assert main(["vgdl", "inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "update order (avatar first, then reverse drawing order): avatar, rock, hero, floor, wall" in out
    assert "EOS (in order, repeats applied again): hero" in out
    assert "   1. rock hero: bounceForward(line 7)\n   2. rock wall: stepBack(line 9)" in out
    assert "  line 12: SpriteCounter stype=hero limit=0 win=False" in out
    assert "not implemented by the engine: bounceForward" in out


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
    assert exit_code(["vgdl", "list"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
