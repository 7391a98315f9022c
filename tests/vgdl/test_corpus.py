"""GVGAI's 104 grid-physics files parse exactly as Java parses them.

The VGDL files are not part of this repository: the test reads them from the folder named by
``GVGAI_VGDL_DIR``, else from ``../shared/vgdl/games/`` beside the checkout. Java's own parse
of each file (``java_structure.jsonl``: update order, collision pairs in processing order with
their effect counts, EOS list, subtypes) and the per-game feature inventory are read from
``../shared/vgdl/data/`` beside the checkout (``GVGAI_VGDL_DATA`` overrides it). Where either
is missing the tests are skipped, saying which.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from gvgai_pcg.vgdl import GameDescription, parse_file
from gvgai_pcg.vgdl.support import IMPLEMENTED, required_features, unsupported_features

ROOT = Path(__file__).resolve().parents[2]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"
INVENTORY = DATA / "inventory.json"

needs_corpus = pytest.mark.skipif(
    not GAMES.is_dir() or not STRUCTURE.is_file(),
    reason=f"GVGAI's VGDL files ({GAMES}) or Java's parse ({STRUCTURE}) are not here; set GVGAI_VGDL_DIR",
)


def java_structure() -> dict[str, dict]:
    rows = [json.loads(line) for line in STRUCTURE.read_text().splitlines() if line.strip()]
    return {Path(row["file"]).name: row for row in rows}


def structure(game: GameDescription) -> dict:
    """The parse in the oracle's shape."""
    return {
        "sprite_order": list(game.sprite_order),
        "pairs": [[pair.first, pair.second, len(pair.effects)] for pair in game.pairs],
        "eos": list(game.eos),
        "subtypes": {name: list(sprite.subtypes) for name, sprite in game.types.items()},
    }


@needs_corpus
def test_every_file_parses_to_java_structure():
    expected = java_structure()
    assert len(expected) == 104
    different = []
    for name, java in expected.items():
        mine = structure(parse_file(GAMES / name))
        different += [f"{name}: {key}" for key in mine if mine[key] != java[key]]
    assert not different, (
        f"{len(expected) - len({d.split(':')[0] for d in different})}/104 equal; {different}"
    )


@needs_corpus
@pytest.mark.skipif(not INVENTORY.is_file(), reason=f"the feature inventory ({INVENTORY}) is not here")
def test_each_file_needs_the_features_the_inventory_lists():
    inventory = json.loads(INVENTORY.read_text())
    different = {}
    for game, facts in inventory.items():
        mine = {feature.name for feature in required_features(parse_file(GAMES / f"{game}.txt"))}
        if mine != set(facts["requirements"]):
            different[game] = sorted(mine ^ set(facts["requirements"]))
    assert not different
    complete = sorted(
        game for game in inventory if not unsupported_features(parse_file(GAMES / f"{game}.txt"))
    )
    assert complete == [
        "boulderdash",
        "camelRace",
        "frogs",
        "infection",
        "painter",
        "racebet",
        "racebet2",
        "solarfox",
        "zelda",
        "zenpuzzle",
    ]


@pytest.mark.skipif(not (DATA / "cover.json").is_file(), reason=f"the corpus notes ({DATA}) are not here")
def test_the_implemented_table_is_the_four_games_features_of_the_corpus_notes():
    assert IMPLEMENTED == set(json.loads((DATA / "cover.json").read_text())["four_features"])
