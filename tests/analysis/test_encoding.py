import numpy as np
import pytest

from gvgai_pcg.analysis.encoding import encode_level, encode_levels, padded_rows, tileset
from gvgai_pcg.levels import Level, human_levels

# A 4x3 Zelda level, smaller than the full 13x9: padded with wall at the right and bottom.
SMALL_ZELDA = """\
wAg.
+1.w
2.3w
"""


def test_hand_made_level_is_encoded_cell_by_cell_at_full_size():
    level = Level.parse(SMALL_ZELDA, "zelda")
    encoded = encode_level(level)
    assert tileset("zelda") == "wAg+123"
    assert encoded.shape == (7, 9, 13) and encoded.dtype == np.uint8
    rows = padded_rows(level)
    assert rows[0] == "wAg." + "w" * 9 and rows[3:] == ["w" * 13] * 6
    for r in range(9):
        for c in range(13):
            char = rows[r][c]
            expected = [1 if char == t else 0 for t in "wAg+123"]
            assert encoded[:, r, c].tolist() == expected, (r, c, char)
    floor = [(r, c) for r in range(9) for c in range(13) if rows[r][c] == "."]
    assert floor == [(0, 3), (1, 2), (2, 1)]
    assert all(encoded[:, r, c].sum() == 0 for r, c in floor)


def test_study_tileset_drops_boulderdash_avatar_and_complete_keeps_it():
    level = human_levels("boulderdash")[0]
    (row, col) = level.find("A")[0]
    assert "A" not in tileset("boulderdash")
    assert encode_level(level)[:, row, col].sum() == 0
    complete = encode_level(level, complete=True)
    assert complete[tileset("boulderdash", complete=True).index("A"), row, col] == 1
    assert "." not in tileset("boulderdash", complete=True)


@pytest.mark.parametrize(
    ("game", "size"), [("zelda", 819), ("solarfox", 770), ("frogs", 4004), ("boulderdash", 2366)]
)
def test_feature_sizes_match_the_study(game, size):
    assert encode_levels(human_levels(game)).shape == (5, size)


def test_frogs_level_4_is_padded_with_a_wall_row_at_the_bottom():
    level = human_levels("frogs")[4]
    assert level.height == 10
    encoded = encode_level(level)
    assert encoded.shape == (13, 11, 28)
    assert encoded[tileset("frogs").index("w"), 10].all()


def test_levels_of_two_games_are_refused():
    with pytest.raises(ValueError, match="exactly one game"):
        encode_levels([human_levels("zelda")[0], human_levels("frogs")[0]])
