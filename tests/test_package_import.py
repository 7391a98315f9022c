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
    expected = [
        "gvgai_pcg/Boulderdash-v0",
        "gvgai_pcg/Frogs-v0",
        "gvgai_pcg/Solarfox-v0",
        "gvgai_pcg/Zelda-v0",
    ]
    assert out.strip() == f"{expected} False"
