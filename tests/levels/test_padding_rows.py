"""The one padding: bottom-right for the engine and the analysis, centred for generators."""

from __future__ import annotations

import pytest

from gvgai_pcg.levels.padding import centre_rows, pad_rows


def test_pad_rows_keeps_the_top_left_corner():
    assert pad_rows(["ab", "cd"], 3, 4, ".") == ["ab..", "cd..", "...."]


def test_centre_rows_puts_the_odd_cell_right_and_below():
    assert centre_rows(["a"], 4, 4, ".") == ["....", ".a..", "....", "...."]


@pytest.mark.parametrize("pad", [pad_rows, centre_rows])
def test_a_grid_too_small_is_refused_naming_the_level(pad):
    with pytest.raises(ValueError, match="level lv4 is 3x1, larger than 2x2"):
        pad(["abc"], 2, 2, ".", "lv4")
