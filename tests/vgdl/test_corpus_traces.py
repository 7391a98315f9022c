"""The Java traces of GVGAI corpus games (``tests/data/vgdl_corpus_traces``) replay through the
generic step, tick by tick, from GVGAI's own VGDL file of each game; GVGAI's zelda, recorded the
same way, is the control that the engine already plays exactly. One longer trace plays labyrinth
until its ``Timeout`` ends it; one on a hand-made level renews labyrinthdual's avatar in place.

GVGAI's files are not in this repository: without the corpus folder (``GVGAI_VGDL_DIR``) every
replay is skipped, saying so; a game the engine refuses is skipped with the engine's one-line
refusal (the feature it lacks). A game the engine runs must match every recorded tick.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl import VGDLError
from gvgai_pcg.vgdl.corpus import ENV_VAR, corpus_dir
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.engine.trace import play_trace

TRACES = Path(__file__).parents[1] / "data" / "vgdl_corpus_traces"
FIELDS = ("tick", "action", "score", "status", "avatar", "sprites")


def trace_files() -> list[Path]:
    return sorted(TRACES.glob("*_lvl*.json"))


def corpus_game(name: str) -> VGDLGame:
    """The generic step on GVGAI's file of ``name``: skipped without the file, or with the
    engine's refusal."""
    folder = corpus_dir()
    if folder is None or not (folder / f"{name}.txt").is_file():
        pytest.skip(f"GVGAI's {name}.txt is not in the corpus folder: set {ENV_VAR}")
    try:
        return VGDLGame.from_file(folder / f"{name}.txt", name=f"vgdl:{name}")
    except VGDLError as error:
        pytest.skip(f"the engine refuses {name}: {error}")


def first_mismatch(expected: list[dict], actual: list[dict]) -> str | None:
    """Where two tick lists first differ, in one message; None when they are equal."""
    for want, got in zip(expected, actual, strict=False):
        want = {key: want[key] for key in FIELDS}
        if got != want:
            return f"tick {want['tick']}:\nexpected {want}\nactual   {got}"
    if len(expected) != len(actual):
        return f"{len(actual)} ticks played, {len(expected)} recorded"
    return None


# the recorded games, and the hand-scripted walks that push (``<level>_pushes``, README)
GAMES = (
    "camelRace",
    "infection",
    "painter",
    "racebet",
    "racebet2",
    "zenpuzzle",
    "zelda",
    "labyrinth",
    "labyrinthdual",
    "shipwreck",
    "surround",
    "whackamole",
    "bait",
    "colourescape",
    "escape",
    "realsokoban",
    "sokoban",
    "thesnowman",
    "watergame",
)
PUSHES = ("bait_lvl1", "escape_lvl0", "realsokoban_lvl0", "sokoban_lvl0", "thesnowman_lvl0", "watergame_lvl1")


def test_every_game_has_its_five_human_levels_recorded():
    names = [path.stem for path in trace_files()]
    scripted = [f"{level}_pushes" for level in PUSHES]
    boxed = [f"infection_boxed_lvl{index}" for index in range(5)]  # its RandomNPCs walled in
    recorded = [f"{game}_lvl{index}" for game in GAMES for index in range(5)]
    assert names == sorted(recorded + scripted + boxed)
    for path in trace_files():
        trace = json.loads(path.read_text())
        assert trace["engine_seeds"] == [0, 1, 2, 3] and trace["ticks"][0]["action"] == "NIL"
        assert len(trace["ticks"]) == len(trace["actions"]) + 1


PUSHED = frozenset({"box", "boxin", "body", "chest", "head"})  # the pushed types of these games
STEPS = {"LEFT": (-10, 0), "RIGHT": (10, 0), "UP": (0, -10), "DOWN": (0, 10)}


@pytest.mark.parametrize("level", PUSHES)
def test_each_hand_scripted_walk_pushes_and_has_a_push_undone(level):
    ticks = json.loads((TRACES / f"{level}_pushes.json").read_text())["ticks"]
    pushes = undone = 0
    for before, tick in zip(ticks, ticks[1:], strict=False):
        if tick["action"] not in STEPS or not tick["avatar"]:
            continue
        dx, dy = STEPS[tick["action"]]
        x, y = before["avatar"]["x"], before["avatar"]["y"]
        if not any(sprite == [name, x + dx, y + dy] for sprite in before["sprites"] for name in PUSHED):
            continue
        moved = (tick["avatar"]["x"], tick["avatar"]["y"]) != (x, y)
        pushes += moved
        undone += not moved
    assert pushes >= 3 and undone >= 1


def test_a_changed_tick_is_the_first_mismatch():
    ticks = json.loads((TRACES / "zelda_lvl0.json").read_text())["ticks"]
    played = [{key: tick[key] for key in FIELDS} for tick in ticks]
    assert first_mismatch(ticks, played) is None
    played[7] = played[7] | {"score": played[7]["score"] + 1}
    assert first_mismatch(ticks, played).startswith("tick 7:")
    assert first_mismatch(ticks, played[:7]) == f"7 ticks played, {len(ticks)} recorded"


# a game the engine runs replays its 120 ticks eagerly in about 1 CPU-second
# with a hand-made level: labyrinthdual's avatar made into its own type by a second red coat
HAND_MADE = ("labyrinthdual_renew.json",)


@pytest.mark.parametrize("path", trace_files() + [TRACES / n for n in HAND_MADE], ids=lambda path: path.stem)
def test_corpus_trace_replays_exactly(path):
    trace = json.loads(path.read_text())
    game = corpus_game(trace["game"])
    level = Level(trace["game"], tuple(trace["level"]), name=path.stem)
    ticks = play_trace(game, level, trace["actions"], exclude=trace["excluded"])
    mismatch = first_mismatch(trace["ticks"], ticks)
    assert mismatch is None, f"{path.name}, {mismatch}"


@pytest.mark.slow  # 1001 ticks: about 10 CPU-seconds
def test_labyrinth_ends_by_timeout_in_the_tick_java_does():
    path = TRACES / "labyrinth_timeout.json"
    trace = json.loads(path.read_text())
    assert (trace["ticks"][-1]["tick"], trace["ticks"][-1]["status"]) == (1000, "lose")
    game = corpus_game(trace["game"])
    level = Level(trace["game"], tuple(trace["level"]), name=path.stem)
    ticks = play_trace(game, level, trace["actions"], exclude=trace["excluded"])
    mismatch = first_mismatch(trace["ticks"], ticks)
    assert mismatch is None, f"{path.name}, {mismatch}"
