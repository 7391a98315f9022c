"""Pictures of generated levels: per-level PNGs from the CLI and the difficulty figure."""

import argparse

import matplotlib.image as mpimg
import pytest

from gvgai_pcg.commands import generate
from gvgai_pcg.generators.pictures import difficulty_figure


def test_generate_writes_text_and_png(tmp_path):
    parser = argparse.ArgumentParser()
    generate.add_arguments(parser)
    args = parser.parse_args(["--game", "frogs", "--difficulty", "0.5", "--out", str(tmp_path), "--png"])
    assert generate.run(args) == 0
    picture = mpimg.imread(tmp_path / "frogs_d0.5_s0.png")
    assert picture.shape[:2] == (110, 280)  # 10 px per cell of the full 28x11 grid
    assert (tmp_path / "frogs_d0.5_s0.txt").read_text().count("A") == 1


def test_png_needs_an_output_folder():
    parser = argparse.ArgumentParser()
    generate.add_arguments(parser)
    with pytest.raises(ValueError, match="--png needs --out"):  # the CLI: one line, exit 2
        generate.run(parser.parse_args(["--game", "zelda", "--png"]))


def test_difficulty_figure_is_written(tmp_path):
    path = difficulty_figure(tmp_path / "figure.png", games=("zelda", "solarfox"), difficulties=(0.0, 1.0))
    assert mpimg.imread(path).shape[0] > 100
