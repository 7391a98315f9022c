"""Level parsing: the human levels load, and every kind of bad input is refused with its place."""

import os
import pickle
import subprocess
import sys

import pytest

from gvgai_pcg.levels import LEVEL_FORMATS, Level, LevelFormatError, human_level, human_levels, resolve_level


@pytest.mark.parametrize("game", sorted(LEVEL_FORMATS))
def test_human_levels_load_with_their_sizes(game):
    levels = human_levels(game)
    fmt = LEVEL_FORMATS[game]
    assert [lv.name for lv in levels] == [f"{game}_lvl{i}" for i in range(5)]
    for level in levels:
        assert level.width == fmt.width
        assert level.height == (10 if level.name == "frogs_lvl4" else fmt.height)
        assert Level.parse(str(level), game) == level


def test_trailing_newlines_are_optional():
    assert Level.parse("wAgw\n", "zelda") == Level.parse("wAgw", "zelda")
    assert Level.parse("wAgw\r\n", "zelda").rows == ("wAgw",)
    assert Level.parse("wwww\nwAgw\n\n\n", "zelda").rows == ("wwww", "wAgw")  # blank lines at the end
    with pytest.raises(LevelFormatError, match="line 2"):
        Level.parse("wwww\n\nwAgw\n", "zelda")  # but not between rows


def test_a_level_named_after_another_game_is_refused(tmp_path):
    path = tmp_path / "boulderdash_custom.txt"
    path.write_text("wwww\nwAgw\nwwww\n")  # parses as zelda too
    for spec in ("boulderdash_lvl0", str(path)):
        with pytest.raises(ValueError, match="boulderdash level, not a zelda one"):
            resolve_level(spec, "zelda")
    assert resolve_level("zelda_lvl1", "zelda") == human_level("zelda", 1)


def test_str_round_trips_a_file(tmp_path):
    path = tmp_path / "zelda_custom.txt"
    path.write_text(str(human_level("zelda", 2)))
    loaded = Level.load(path)
    assert loaded == human_level("zelda", 2) and loaded.name == "zelda_custom"
    assert resolve_level(str(path)) == loaded
    assert resolve_level("zelda_lvl2") == human_level("zelda", 2)


def refused(text: str, game: str = "zelda", tmp_path=None) -> LevelFormatError:
    path = tmp_path / f"{game}_bad.txt"
    path.write_text(text)
    with pytest.raises(LevelFormatError) as info:
        Level.load(path)
    assert str(path) in str(info.value)
    return info.value


def test_bad_character_names_line_column_and_valid_chars(tmp_path):
    error = refused("wwww\nwA.w\nw.Zw\nwwww\n", tmp_path=tmp_path)
    assert (error.line, error.column) == (3, 3)
    assert "'Z'" in str(error) and "line 3, column 3" in str(error)
    assert "w . A + g 1 2 3" in str(error)


def test_ragged_rows_are_refused(tmp_path):
    error = refused("wwww\nwA.w\nw.w\nwwww\n", tmp_path=tmp_path)
    assert (error.line, error.column) == (3, 4) and "ragged" in str(error)


def test_empty_file_is_refused(tmp_path):
    assert "empty" in str(refused("\n", tmp_path=tmp_path))
    assert "empty" in str(refused("", tmp_path=tmp_path))


def test_no_avatar_and_two_avatars_are_refused(tmp_path):
    assert "no avatar" in str(refused("wwww\nw.gw\nwwww\n", tmp_path=tmp_path))
    error = refused("wwww\nwAAw\nwwww\n", tmp_path=tmp_path)
    assert (error.line, error.column) == (2, 3) and "second avatar" in str(error)
    error = refused("wwwww\nwA.Bw\n", game="frogs", tmp_path=tmp_path)
    assert (error.line, error.column) == (2, 4)


def test_grid_larger_than_the_game_is_refused(tmp_path):
    error = refused("w" * 14 + "\n" + "wA" + "." * 12 + "\n", tmp_path=tmp_path)
    assert "at most 13x9" in str(error)


def test_unknown_game_lists_the_games():
    with pytest.raises(ValueError, match="boulderdash, frogs, solarfox, zelda"):
        Level.parse("A", "pacman")


def test_a_level_unpickled_in_another_process_hashes_as_that_process_does(tmp_path):
    """A Level keeps its hash; one sent to a worker (string hashes differ per process) must
    still find, and equal, the same level built there."""
    level = human_levels("zelda")[0]
    path = tmp_path / "level.pkl"
    path.write_bytes(pickle.dumps(level))
    script = (
        "import pickle, sys; from gvgai_pcg.levels import Level; "
        f"loaded = pickle.loads(open({str(path)!r}, 'rb').read()); "
        "built = Level(loaded.game, loaded.rows); "
        "sys.exit(0 if hash(loaded) == hash(built) and {built: 1}.get(loaded) == 1 else 1)"
    )
    for hash_seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": hash_seed}
        assert subprocess.run([sys.executable, "-c", script], env=env).returncode == 0


def test_a_byte_order_mark_and_crlf_line_ends_are_accepted(tmp_path):
    path = tmp_path / "zelda_windows.txt"
    path.write_bytes(b"\xef\xbb\xbfwwwww\r\nwA+gw\r\nwwwww\r\n")
    assert Level.load(path).rows == ("wwwww", "wA+gw", "wwwww")
    assert Level.parse("\ufeffwAgw\rwwww\r", "zelda").rows == ("wAgw", "wwww")  # and old Mac ends


def test_a_file_that_is_not_utf8_is_refused_with_its_name_and_place(tmp_path):
    path = tmp_path / "zelda_latin1.txt"
    path.write_bytes("wwww\nwA\xe9w\n".encode("latin-1"))
    with pytest.raises(LevelFormatError) as info:
        Level.load(path)
    assert str(info.value).startswith(f"{path}, line 2, column 3: not UTF-8 text (byte 0xe9")
    (tmp_path / "zelda_utf16.txt").write_bytes("wAgw\n".encode("utf-16"))
    with pytest.raises(LevelFormatError, match="zelda_utf16.txt, line 1, column 1: not UTF-8 text"):
        resolve_level(str(tmp_path / "zelda_utf16.txt"), "zelda")


def test_a_level_that_is_neither_a_name_nor_a_file_is_named_in_one_line():
    with pytest.raises(
        FileNotFoundError, match=r"'nosuch': no such level; expected a human level's name \(zelda_lvl0"
    ):
        resolve_level("nosuch", "zelda")
