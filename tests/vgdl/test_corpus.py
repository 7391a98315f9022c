"""GVGAI's 104 grid-physics files parse as Java parses them; their rules classify as the notes do.

The VGDL files are not part of this repository: the test reads them from the folder named by
``GVGAI_VGDL_DIR``, else from ``../shared/vgdl/games/`` beside the checkout. Java's own parse
of each file (``java_structure.jsonl``: update order, collision pairs in processing order with
their effect counts, EOS list, subtypes), the per-game feature inventory and the kind of every
rule pair (``rule_order.json``) are read from
``../shared/vgdl/data/`` beside the checkout (``GVGAI_VGDL_DATA`` overrides it). Where either
is missing the tests are skipped, saying which.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from gvgai_pcg.vgdl import GameDescription, parse_file
from gvgai_pcg.vgdl.kinds import RANDOM_EFFECTS, rule_kind
from gvgai_pcg.vgdl.plan import analyse, compile_plan
from gvgai_pcg.vgdl.support import IMPLEMENTED, STUDY_FEATURES, required_features, unsupported_features

ROOT = Path(__file__).resolve().parents[2]
GAMES = Path(os.environ.get("GVGAI_VGDL_DIR", ROOT.parent / "shared" / "vgdl" / "games"))
DATA = Path(os.environ.get("GVGAI_VGDL_DATA", ROOT.parent / "shared" / "vgdl" / "data"))
STRUCTURE = DATA / "java_structure.jsonl"
INVENTORY = DATA / "inventory.json"
RULE_ORDER = DATA / "rule_order.json"
# The games the four study games' features complete (CORPUS.md, "Staging"), those that Timeout
# then completes, and those that bounceForward, killBoth and undoAll complete after it.
TEN_GAMES = [
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
TIMEOUT_GAMES = ["labyrinth", "labyrinthdual", "shipwreck", "surround", "whackamole"]
SOKOBAN_FAMILY = [
    "bait",
    "bomberman",
    "clusters",
    "colourescape",
    "cookmepasta",
    "escape",
    "modality",
    "realsokoban",
    "sokoban",
    "tercio",
    "thesnowman",
    "watergame",
]
# of those, the games whose every feature the engine implements (the rest: see docs/games.md)
READY_GAMES = TEN_GAMES + TIMEOUT_GAMES + SOKOBAN_FAMILY

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
    assert complete == sorted(TEN_GAMES + TIMEOUT_GAMES + SOKOBAN_FAMILY)


@pytest.mark.skipif(not (DATA / "cover.json").is_file(), reason=f"the corpus notes ({DATA}) are not here")
def test_the_study_features_table_is_the_four_games_features_of_the_corpus_notes():
    assert STUDY_FEATURES == set(json.loads((DATA / "cover.json").read_text())["four_features"])
    assert IMPLEMENTED == STUDY_FEATURES | {"Timeout", "bounceForward", "killBoth", "undoAll"}


@needs_corpus
@pytest.mark.skipif(not RULE_ORDER.is_file(), reason=f"the rule classification ({RULE_ORDER}) is not here")
def test_each_rule_kind_agrees_with_the_corpus_classification():
    games = json.loads(RULE_ORDER.read_text())["games"]
    assert len(games) == 104
    different = []
    for game, facts in games.items():
        description = parse_file(GAMES / f"{game}.txt")
        pairs = [(effect, second) for effect in description.effects for second in effect.seconds]
        assert len(pairs) == len(facts["rules"]), game
        for (effect, second), (first, _, name, kind, random) in zip(pairs, facts["rules"], strict=True):
            assert (effect.first, effect.name) == (first, name), game
            mine = rule_kind(description, effect, second)[0], effect.name in RANDOM_EFFECTS
            if mine != (kind, random):
                different.append(f"{game} line {effect.line} {first} {second}: {mine} != {(kind, random)}")
    assert not different, f"{len(different)} of 1,546 pairs differ: {different}"


@needs_corpus
def test_every_file_has_a_plan_and_the_ready_games_compile():
    ready = []
    for path in sorted(GAMES.glob("*.txt")):
        if "_lvl" in path.stem:
            continue
        game = parse_file(path)
        plan = analyse(game)
        assert set(plan.types) == {name for name in game.sprite_order if game.types[name].java_class}
        reached = {name for rule in plan.rules() for name in rule.firsts + rule.seconds}
        counted = {name for end in plan.terminations for names in end.counted for name in names}
        assert reached | counted <= set(plan.types), path.name  # the step needs no other type
        if not unsupported_features(game):
            ready.append(compile_plan(game).path)
    assert sorted(Path(path).stem for path in ready) == sorted(READY_GAMES)
