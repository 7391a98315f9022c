"""Bad input to a command ends in one line naming the problem, not a traceback."""

from __future__ import annotations

import subprocess
import sys

import pytest

from gvgai_pcg.cli import main
from tests.waiting import PATIENCE_S


def _error_of(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    return err


def test_a_malformed_level_file_names_file_line_and_column(tmp_path, capsys):
    bad = tmp_path / "zelda_bad.txt"
    bad.write_text("wwww\nwAgw\nwwXw\n")
    err = _error_of(["play", "--game", "zelda", "--level", str(bad)], capsys)
    assert f"{bad}, line 3, column 3" in err and "valid characters" in err


def test_a_level_file_that_is_not_utf8_is_named(tmp_path, capsys):
    bad = tmp_path / "zelda_latin1.txt"
    bad.write_bytes(b"wwwww\nwA\xe9gw\nwwwww\n")
    err = _error_of(["evaluate", "--game", "zelda", "--levels", str(bad), "--episodes", "1"], capsys)
    assert f"{bad}, line 2, column 3: not UTF-8 text (byte 0xe9 cannot be decoded)" in err


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["play", "--game", "zelda", "--level", "missing_file.txt"], "'missing_file.txt': no such level"),
        (["play", "--game", "zelda", "--level", "zelda_lvl7"], "0..4"),
        (["play", "--game", "zelda", "--level", "frogs_lvl0"], "frogs level, not a zelda one"),
        (["analyze", "--game", "zelda", "--count", "30", "--eps", "-1"], "eps"),
    ],
)
def test_bad_input_is_one_line(argv, says, capsys, tmp_path):
    if argv[0] == "analyze":
        argv = [*argv, "--out", str(tmp_path)]
    assert says in _error_of(argv, capsys)


def test_output_cut_short_by_the_reader_is_not_an_error():
    generate = "generate --game zelda --difficulty 0:1:0.01 --count 5"
    command = f"{sys.executable} -m gvgai_pcg.cli {generate} | head -1"
    done = subprocess.run(command, shell=True, capture_output=True, text=True, timeout=PATIENCE_S)
    assert done.stdout == "# game=zelda d=0 seed=0\n"
    assert done.stderr == ""


def _refusing_train(cfg, run_dir, **kwargs):
    raise OSError(f"{run_dir} cannot be written (a refusal from inside the Hydra app)")


def test_a_train_refusal_inside_the_hydra_app_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("GVGAI_PCG_DEBUG", raising=False)
    monkeypatch.setattr("gvgai_pcg.rl.train", _refusing_train)
    err = _error_of(["train", "regimen=lv", "total_frames=80", f"out_dir={tmp_path}", "run_name=run"], capsys)
    refusal = f"{tmp_path / 'run'} cannot be written (a refusal from inside the Hydra app)"
    assert err == f"gvgai-pcg train: error: {refusal}\n"


def test_gvgai_pcg_debug_shows_the_traceback_of_a_train_refusal(tmp_path, monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_DEBUG", "1")
    monkeypatch.setattr("gvgai_pcg.rl.train", _refusing_train)
    with pytest.raises(OSError, match="a refusal from inside the Hydra app"):
        main(["train", "regimen=lv", "total_frames=80", f"out_dir={tmp_path}", "run_name=run"])
