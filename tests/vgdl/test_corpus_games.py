"""GVGAI corpus games as registered games (``gvgai_pcg.vgdl.corpus_games``): found in the folder
``GVGAI_VGDL_DIR`` names, registered when the generic step runs them, refused in one line
otherwise (what to set without the folder, the engine's refusal with it).

The wiring is tested on a folder holding the package's own Zelda description under another name
(a game the engine runs today); the six corpus games are tested where the real corpus is present,
and skipped with the engine's refusal while it has no kernel for them.
"""

from __future__ import annotations

import shutil

import pytest

from gvgai_pcg.cli import main
from gvgai_pcg.games import registry
from gvgai_pcg.levels import human_level, human_levels
from gvgai_pcg.vgdl import corpus, corpus_games
from gvgai_pcg.vgdl.corpus import ENV_VAR
from gvgai_pcg.vgdl.registry import DESCRIPTIONS

REFUSED = """BasicGame
    SpriteSet
        hero > MovingAvatar
        bomb > Bomber stype=hero
    TerminationSet
        SpriteCounterMore stype=hero limit=0 win=True
"""


def reset_registry(monkeypatch: pytest.MonkeyPatch) -> None:
    """The registry as a new process finds it (corpus games found again on first use), restored
    after the test."""
    registry.registered_games()
    own = {name: spec for name, spec in registry._SPECS.items() if corpus_games.corpus_file(name) is None}
    monkeypatch.setattr(registry, "_SPECS", own)
    monkeypatch.setattr(registry, "_GAMES", dict(registry._GAMES))
    monkeypatch.setattr(registry, "_found_builtins", False)


@pytest.fixture
def fresh_registry(monkeypatch):
    reset_registry(monkeypatch)


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """A corpus folder with ``zcopy`` (the package's Zelda description and Zelda's human levels)
    and ``refused`` (a Bomber, which the engine has no kernel for), named by GVGAI_VGDL_DIR; the
    corpus games looked for are these two."""
    shutil.copy(DESCRIPTIONS / "zelda.txt", tmp_path / "zcopy.txt")
    (tmp_path / "refused.txt").write_text(REFUSED)
    for index in range(5):
        (tmp_path / f"zcopy_lvl{index}.txt").write_text("\n".join(human_level("zelda", index).rows) + "\n")
        (tmp_path / f"refused_lvl{index}.txt").write_text("wwww\nwA.w\nwwww\n")
    monkeypatch.setattr(corpus_games, "CORPUS_GAMES", ("refused", "zcopy"))
    monkeypatch.setenv(ENV_VAR, str(tmp_path))
    reset_registry(monkeypatch)
    return tmp_path


def test_without_the_folder_a_corpus_game_is_refused_saying_what_to_set(
    fresh_registry, monkeypatch, tmp_path
):
    monkeypatch.delenv(ENV_VAR, raising=False)
    monkeypatch.setattr(corpus, "_CHECKOUT_DEFAULT", tmp_path / "absent")
    assert "painter" not in registry.registered_games()
    with pytest.raises(ValueError) as error:
        registry.get_game_spec("camelrace")
    assert str(error.value) == (
        "game 'camelrace' is a GVGAI corpus game, not shipped with this package: "
        "set GVGAI_VGDL_DIR to a folder holding GVGAI's camelRace.txt and camelRace_lvl0..4.txt"
    )
    with pytest.raises(ValueError, match="^unknown game 'paintr'; registered games are: boulderdash"):
        registry.get_game_spec("paintr")


def test_play_refuses_a_corpus_game_without_the_folder_in_one_line(
    fresh_registry, monkeypatch, tmp_path, capsys
):
    monkeypatch.delenv(ENV_VAR, raising=False)
    monkeypatch.setattr(corpus, "_CHECKOUT_DEFAULT", tmp_path / "absent")
    with pytest.raises(SystemExit) as code:
        main(["play", "--game", "painter"])
    assert code.value.code == 2
    assert (
        capsys.readouterr()
        .err.splitlines()[-1]
        .endswith(
            "argument --game: game 'painter' is a GVGAI corpus game, not shipped with this package: "
            "set GVGAI_VGDL_DIR to a folder holding GVGAI's painter.txt and painter_lvl0..4.txt"
        )
    )


def test_a_corpus_folder_registers_the_games_the_engine_runs(folder):
    games = registry.registered_games()
    assert "zcopy" in games and "refused" not in games
    spec = registry.get_game_spec("zcopy")
    assert spec.title == "Zcopy" and spec.human_level_files == str(folder / "zcopy_lvl{index}.txt")
    zelda = registry.get_game_spec("zelda").level_format
    assert sorted(spec.level_format.chars) == sorted(zelda.chars)
    assert (spec.level_format.avatar_chars, spec.level_format.height, spec.level_format.width) == ("A", 9, 13)
    assert [level.rows for level in human_levels("zcopy")] == [level.rows for level in human_levels("zelda")]
    assert human_level("zcopy", 2).name == "zcopy_lvl2"
    with pytest.raises(ValueError) as error:
        registry.get_game_spec("refused")
    message = str(error.value)
    assert message.startswith(f"game 'refused' cannot be played yet: {folder / 'refused.txt'}:")
    assert "Bomber" in message and "\n" not in message


def test_vgdl_list_names_the_corpus_games_played_and_refused(folder, capsys):
    assert main(["vgdl", "list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[:4] == ["boulderdash", "frogs", "solarfox", "zelda"]
    assert f"zcopy\tcorpus: {folder / 'zcopy.txt'}" in lines
    refused = [line for line in lines if line.startswith("refused\tcorpus, refused: game 'refused' cannot")]
    assert len(refused) == 1 and "Bomber" in refused[0]


def test_a_registered_corpus_game_plays_as_an_env_and_a_gymnasium_id(folder, monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")  # a few eager ticks: compiling costs a minute
    import gymnasium
    import torch

    from gvgai_pcg.envs.gvgai_env import GVGAIEnv
    from gvgai_pcg.envs.gym_registration import env_id, register_envs

    env = GVGAIEnv("zcopy", num_envs=2, seed=0)
    state = env.reset()
    assert state["tiles"].shape[0] == 2 and env.game.actions[3] == "RIGHT"
    state["action"] = torch.tensor([3, 3])
    assert env.step(state)["next", "reward"].shape[0] == 2
    try:
        ids = register_envs()
        assert env_id("Zcopy") in ids and env_id("Refused") in ids
        observation, _ = gymnasium.make(env_id("Zcopy")).reset(seed=0)
        assert observation.shape[1:] == (9, 13)
        with pytest.raises(ValueError, match="^game 'refused' cannot be played yet"):
            gymnasium.make(env_id("Refused"))
    finally:
        for title in ("Zcopy", "Refused"):
            gymnasium.registry.pop(env_id(title), None)


@pytest.mark.parametrize("stem", corpus_games.CORPUS_GAMES)
def test_each_corpus_game_plays_or_is_refused_in_one_line(stem, fresh_registry, monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")  # a reset tick: compiling costs a minute
    folder = corpus.corpus_dir()
    if folder is None or not (folder / f"{stem}.txt").is_file():
        pytest.skip(f"GVGAI's {stem}.txt is not in the corpus folder: set {ENV_VAR}")
    name = corpus_games.game_name(stem)
    if name not in registry.registered_games():
        reason = corpus_games.refusal(name)
        assert reason.startswith(f"game {name!r} cannot be played yet: {folder / stem}.txt:")
        assert "\n" not in reason
        pytest.skip(reason)
    assert len(human_levels(name)) == 5
    from gvgai_pcg.envs.gvgai_env import GVGAIEnv

    env = GVGAIEnv(name, num_envs=2, seed=0)
    assert env.reset()["tiles"].shape[0] == 2


def test_an_unlisted_corpus_game_is_refused_with_what_it_lacks_or_as_unverified(folder):
    shutil.copy(DESCRIPTIONS / "zelda.txt", folder / "unchecked.txt")
    (folder / "lacking.txt").write_text(REFUSED)
    with pytest.raises(ValueError, match=r"'unchecked' .* is not verified against Java yet"):
        registry.get_game_spec("unchecked")
    with pytest.raises(ValueError, match=r"'lacking' cannot be played yet: .*lacking.txt:4: Bomber is not"):
        registry.get_game_spec("lacking")


def test_the_games_page_has_a_row_per_file_saying_what_it_lacks(folder, tmp_path_factory, capsys):
    shutil.copy(DESCRIPTIONS / "zelda.txt", folder / "unchecked.txt")
    traces = tmp_path_factory.mktemp("traces")
    for index in range(3):
        (traces / f"zcopy_lvl{index}.json").write_text("{}")
    out = tmp_path_factory.mktemp("docs") / "games.md"
    assert main(["vgdl", "games", "--out", str(out), "--traces", str(traces)]) == 0
    assert capsys.readouterr().out.startswith("1 of 3 games play")
    page = out.read_text()
    assert "| zcopy | yes | 11 | - | 3 Java traces, replayed tick by tick |" in page
    assert "| refused | no | 3 | Bomber, SpriteCounterMore | - |" in page  # and MovingAvatar
    assert "| unchecked | no | 11 | - | - |" in page
    assert "- 1 more have every feature but do not play yet (no Java check, or the generic step" in page
    assert "refuses how they use one: its refusal names it): unchecked." in page


def test_the_games_page_refuses_a_missing_traces_folder_and_writes_nothing(folder, tmp_path, capsys):
    out = tmp_path / "games.md"
    with pytest.raises(SystemExit) as stop:
        main(["vgdl", "games", "--out", str(out), "--traces", str(tmp_path / "none")])
    assert stop.value.code == 2 and "no traces folder" in capsys.readouterr().err
    assert not out.exists()


def test_docs_games_page_is_what_the_corpus_and_traces_give(fresh_registry):
    from pathlib import Path

    from gvgai_pcg.vgdl.games_page import game_rows, games_markdown

    folder = corpus.corpus_dir()
    if folder is None or len(corpus.vgdl_games()) < 100:
        pytest.skip(f"GVGAI's VGDL files are not here: set {ENV_VAR}")
    root = Path(__file__).resolve().parents[2]
    page = games_markdown(game_rows(folder, root / "tests/data/vgdl_corpus_traces"))
    assert (root / "docs/games.md").read_text() == page, "rebuild: gvgai-pcg vgdl games --out docs/games.md"
