"""``import gvgai_pcg`` registers the Gymnasium ids and stays free of torch."""

import subprocess
import sys


def test_import_registers_gymnasium_ids_without_torch():
    code = (
        "import sys, gymnasium, gvgai_pcg;"
        "ids = sorted(k for k in gymnasium.registry if k.startswith('gvgai_pcg/'));"
        "print(ids, 'torch' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    # the study's four, and GVGAI's fifteen corpus games, whose ids exist without the corpus folder
    # so that making one says in one line what to set (gvgai_pcg.vgdl.corpus_games)
    study = ["Boulderdash", "Frogs", "Solarfox", "Zelda"]
    corpus = ["CamelRace", "Infection", "Labyrinth", "Labyrinthdual", "Painter", "Racebet", "Racebet2"]
    corpus += ["Zenpuzzle", "Bait", "Colourescape", "Escape", "Realsokoban", "Sokoban", "Thesnowman"]
    corpus += ["Watergame"]
    expected = sorted(f"gvgai_pcg/{name}-v0" for name in study + corpus)
    assert out.strip() == f"{expected} False"
