"""The generic step runs Solarfox from a VGDL description exactly as the hand-written engine does.

The description is the package's own (``descriptions/solarfox.txt``, written from RULES.md §5),
whose parse must equal Java's parse of GVGAI's solarfox.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from gvgai_pcg.vgdl import parse_file

HERE = Path(__file__).parent
OWN_SOLARFOX = HERE / "descriptions" / "solarfox.txt"
ROOT = HERE.parents[1]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"


@pytest.mark.skipif(not STRUCTURE.is_file(), reason=f"Java's parse ({STRUCTURE}) is not here")
def test_own_description_parses_as_java_parses_gvgai_solarfox():
    rows = [json.loads(line) for line in STRUCTURE.read_text().splitlines() if line.strip()]
    java = next(row for row in rows if Path(row["file"]).name == "solarfox.txt")
    game = parse_file(OWN_SOLARFOX)
    assert list(game.sprite_order) == java["sprite_order"]
    assert [[pair.first, pair.second, len(pair.effects)] for pair in game.pairs] == java["pairs"]
    assert list(game.eos) == java["eos"]
    assert {name: list(sprite.subtypes) for name, sprite in game.types.items()} == java["subtypes"]
