"""The generic step runs Boulderdash from a VGDL description exactly as the hand-written engine does.

The description is the package's own (``descriptions/boulderdash.txt``, written from RULES.md §7),
whose parse must equal Java's parse of GVGAI's boulderdash.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from gvgai_pcg.vgdl import parse_file

HERE = Path(__file__).parent
OWN_BOULDERDASH = HERE / "descriptions" / "boulderdash.txt"
ROOT = HERE.parents[1]
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"


@pytest.mark.skipif(not STRUCTURE.is_file(), reason=f"Java's parse ({STRUCTURE}) is not here")
def test_own_description_parses_as_java_parses_gvgai_boulderdash():
    rows = [json.loads(line) for line in STRUCTURE.read_text().splitlines() if line.strip()]
    java = next(row for row in rows if Path(row["file"]).name == "boulderdash.txt")
    game = parse_file(OWN_BOULDERDASH)
    assert list(game.sprite_order) == java["sprite_order"]
    assert [[pair.first, pair.second, len(pair.effects)] for pair in game.pairs] == java["pairs"]
    assert list(game.eos) == java["eos"]
    assert {name: list(sprite.subtypes) for name, sprite in game.types.items()} == java["subtypes"]
