"""``gvgai-pcg generate`` through its command module."""

from __future__ import annotations

import argparse

import pytest

from gvgai_pcg.commands import generate as command
from gvgai_pcg.generators import generate_level


def parse(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    return parser.parse_args(list(argv))


def test_prints_levels_with_headers(capsys):
    assert command.run(parse("--game", "zelda", "--difficulty", "0.5", "--count", "2", "--seed", "5")) == 0
    out = capsys.readouterr().out
    expected = "".join(f"# game=zelda d=0.5 seed={s}\n{generate_level('zelda', 0.5, s)}" for s in (5, 6))
    assert out == expected


def test_sweep_writes_files(tmp_path, capsys):
    args = parse("--game", "boulderdash", "--difficulty", "0:1:0.5", "--count", "2", "--out", str(tmp_path))
    assert command.run(args) == 0
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == sorted(f"boulderdash_d{d:g}_s{s}.txt" for d in (0, 0.5, 1) for s in (0, 1))
    assert (tmp_path / "boulderdash_d0.5_s1.txt").read_text() == str(generate_level("boulderdash", 0.5, 1))


def test_sweep_includes_stop():
    assert command.difficulties("0:1:0.1") == pytest.approx([i / 10 for i in range(11)])
    assert command.difficulties("0.3") == [0.3]


@pytest.mark.parametrize("spec", ["2", "0:2:0.5", "1:0:0.1", "0:1:0", "a:b", "nan", "0:inf:1", "0:1:1e-9"])
def test_bad_difficulty_exits(spec, capsys):
    with pytest.raises(SystemExit):
        parse("--game", "zelda", "--difficulty", spec)
    assert "difficulty" in capsys.readouterr().err


def test_unknown_game_exits(capsys):
    with pytest.raises(SystemExit):
        parse("--game", "pacman")
    assert "zelda" in capsys.readouterr().err


def test_close_difficulties_get_distinct_file_names(tmp_path, capsys):
    args = parse("--game", "zelda", "--difficulty", "0.1234561:0.1234564:0.0000001", "--out", str(tmp_path))
    assert command.run(args) == 0
    assert len(list(tmp_path.iterdir())) == 4


@pytest.mark.parametrize(
    ("difficulty", "tag"),
    [(0.0, "0"), (1.0, "1"), (0.5, "0.5"), (1e-5, "0.00001"), (0.37000000000000005, "0.37")],
)
def test_level_names_write_the_difficulty_as_plain_decimals(difficulty, tag):
    from gvgai_pcg.commands.analyze import DIFFICULTY_IN_NAME

    name = generate_level("zelda", difficulty, 3).name
    assert name == f"zelda_d{tag}_s3"
    assert float(DIFFICULTY_IN_NAME.search(name).group(1)) == pytest.approx(difficulty)
