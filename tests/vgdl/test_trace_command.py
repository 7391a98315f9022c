"""``gvgai-pcg vgdl trace``: a level played through the generic step, written in the golden format.

Zelda's own description replays each of Java's Zelda golden traces from the trace's level and
actions to the same file (every field the golden format has); bad input is refused in one line
naming the culprit, with exit 2 and nothing written.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gvgai_pcg.cli import main
from gvgai_pcg.vgdl.registry import registered_game
from tests.games.golden_replay import golden_files

GOLDEN_KEYS = ("tick", "action", "score", "status", "avatar", "sprites")


def trace(tmp_path: Path, golden: dict, *extra: str, game: str = "zelda") -> list[str]:
    level = tmp_path / "level.txt"
    level.write_text("\n".join(golden["level"]) + "\n")
    actions = ",".join(golden["actions"])
    return ["vgdl", "trace", game, str(level), "--actions", actions, *extra]


@pytest.mark.parametrize("path", golden_files("zelda"), ids=lambda p: p.stem)
def test_zelda_trace_equals_the_java_golden_trace(path, tmp_path, capsys):
    golden = json.loads(path.read_text())
    out = tmp_path / "trace.json"
    assert main([*trace(tmp_path, golden, "--exclude", "wall,floor", "--json", str(out))]) == 0
    assert f"{len(golden['ticks'])} ticks" in capsys.readouterr().out
    written = json.loads(out.read_text())
    assert written["level"] == golden["level"] and written["actions"] == golden["actions"]
    assert [{key: tick[key] for key in GOLDEN_KEYS} for tick in written["ticks"]] == golden["ticks"]


def test_every_type_is_listed_unless_excluded_and_a_path_names_the_game(tmp_path):
    golden = json.loads(golden_files("zelda")[0].read_text())
    out = tmp_path / "trace.json"
    path = str(registered_game("zelda").description)
    assert main([*trace(tmp_path, golden, "--seed", "3", "--json", str(out), game=path)]) == 0
    first = json.loads(out.read_text())["ticks"][0]
    walls = sum(row.count("w") for row in golden["level"])
    assert [name for name, _, _ in first["sprites"]].count("wall") == walls
    assert "floor" in {name for name, _, _ in first["sprites"]}
    assert first["avatar"]["type"] == "nokey" and "nokey" not in {name for name, _, _ in first["sprites"]}


def refused(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    return err


def test_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, capsys):
    golden = json.loads(golden_files("zelda")[0].read_text())
    out = tmp_path / "out" / "trace.json"
    base = trace(tmp_path, golden)
    assert "unknown VGDL game 'nosuch'" in refused(
        [*base[:2], "nosuch", *base[3:], "--json", str(out)], capsys
    )
    missing = str(tmp_path / "absent.txt")
    assert f"cannot read level {missing}" in refused(
        [*base[:3], missing, *base[4:], "--json", str(out)], capsys
    )
    bad_action = [*base[:5], "DOWN,JUMP", "--json", str(out)]
    assert "unknown action 'JUMP'" in refused(bad_action, capsys)
    assert "no sprite type 'lava'" in refused([*base, "--exclude", "lava", "--json", str(out)], capsys)
    (tmp_path / "bad.txt").write_text("wA?w\n")
    bad_level = [*base[:3], str(tmp_path / "bad.txt"), *base[4:], "--json", str(out)]
    assert "character '?'" in refused(bad_level, capsys)
    assert not out.parent.exists()
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    assert f"cannot write {blocked / 'trace.json'}" in refused(
        [*base, "--json", str(blocked / "trace.json")], capsys
    )
    folder = tmp_path / "folder"
    (folder / "trace.json").mkdir(parents=True)  # OUT is a folder: refused, the folder left as it was
    assert f"cannot write {folder / 'trace.json'}" in refused(
        [*base, "--json", str(folder / "trace.json")], capsys
    )
    assert [path.name for path in folder.iterdir()] == ["trace.json"] and not any(
        (folder / "trace.json").iterdir()
    )
