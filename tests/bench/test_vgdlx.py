"""VGDLx beside ours: its table and targets from fake rates, where its game descriptions come
from, and the one line when it is missing. Nothing here runs JAX (the one real measurement is
slow, and runs only where VGDLx and GVGAI's descriptions are at hand)."""

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest
import torch

from gvgai_pcg.bench import jobs as bench_jobs
from gvgai_pcg.bench import peers as bench_peers
from gvgai_pcg.bench import vgdlx as bench_vgdlx
from gvgai_pcg.bench.peers import Timed
from gvgai_pcg.bench.throughput import Rate


def _timed(median: float, setup_s: float = 0.0) -> Timed:
    return Timed(Rate(median, median / 2, median * 2), setup_s, cores=1.0, resets=0)


def test_the_peer_modules_import_jax_only_inside_the_functions_that_measure():
    for module in (bench_vgdlx, bench_peers, bench_jobs):
        tree = ast.parse(Path(module.__file__).read_text())
        top = [node for node in tree.body if isinstance(node, ast.Import | ast.ImportFrom)]
        names = {alias.name for node in top if isinstance(node, ast.Import) for alias in node.names}
        names |= {node.module for node in top if isinstance(node, ast.ImportFrom)}
        assert not {name.split(".")[0] for name in names} & {"jax", "vgdl_jax", "xminigrid", "griddly"}


def test_the_table_has_a_row_per_game_and_batch_with_ours_over_vgdlx():
    rows = [
        bench_vgdlx.VgdlxRow("zelda", 64, _timed(60_000), 1, _timed(50_000, setup_s=12.34)),
        bench_vgdlx.VgdlxRow("frogs", 4096, _timed(400_000), 2, _timed(20_000)),
    ]
    lines = bench_vgdlx.vgdlx_lines(rows)
    header = next(line for line in lines if line.startswith("| game |"))
    table = [line for line in lines if line.startswith("| zelda") or line.startswith("| frogs")]
    assert [line.count("|") for line in table] == [header.count("|")] * 2
    assert table[0] == "| zelda | 64 | 60,000 (30,000) | 1 | 50,000 (25,000) | 1.20x | 1.0, 1.0 | 12.3 |"
    assert "| 20.00x |" in table[1]


def test_every_game_is_held_to_3x_at_64_and_20x_at_4096_and_unmeasured_ones_say_so():
    rows = [
        bench_vgdlx.VgdlxRow("zelda", 64, _timed(60_000), 1, _timed(20_000)),
        bench_vgdlx.VgdlxRow("zelda", 4096, _timed(400_000), 2, _timed(40_000)),
    ]
    checks = {check.what: check.met for check in bench_vgdlx.vgdlx_checks(rows)}
    assert checks == {
        "zelda tiles at B = 64 / VGDLx": True,
        "zelda tiles at B = 4,096 / VGDLx": False,
        "frogs tiles at B = 64 / VGDLx": None,
        "frogs tiles at B = 4,096 / VGDLx": None,
        "boulderdash tiles at B = 64 / VGDLx": None,
        "boulderdash tiles at B = 4,096 / VGDLx": None,
    }


def test_without_vgdlx_the_section_says_how_to_install_it(monkeypatch):
    monkeypatch.setattr(bench_vgdlx, "vgdlx_installed", lambda: False)
    section = bench_vgdlx.vgdlx_section(("zelda", "solarfox"), (64,), min_seconds=0.0)
    assert section.text == f"\n### VGDLx\n\n{bench_vgdlx.NOT_INSTALLED}\n"
    assert [check.met for check in section.checks] == [None, None]  # zelda at 64 and 4,096
    assert bench_vgdlx.vgdlx_section(("solarfox",), (64,)).text == ""  # VGDLx has no Solarfox


def test_without_the_descriptions_the_section_says_where_to_point(monkeypatch, tmp_path):
    monkeypatch.setattr(bench_vgdlx, "vgdlx_installed", lambda: True)
    monkeypatch.setenv(bench_vgdlx.GAMES_VARIABLE, str(tmp_path))
    monkeypatch.setattr(bench_vgdlx, "measure_rows", lambda *args: pytest.fail("measured"))
    section = bench_vgdlx.vgdlx_section(("frogs",), (64, 4096), min_seconds=0.0)
    assert bench_vgdlx.NO_DESCRIPTIONS in section.text and f"{tmp_path}/frogs.txt" in section.text
    assert len(section.checks) == 2


def test_the_descriptions_come_from_the_variables_folder_or_one_download_into_the_cache(
    monkeypatch, tmp_path
):
    (tmp_path / "zelda.txt").write_text("BasicGame\n")
    monkeypatch.setenv(bench_vgdlx.GAMES_VARIABLE, str(tmp_path))
    assert bench_vgdlx.game_description("zelda") == "BasicGame\n"
    with pytest.raises(FileNotFoundError, match="frogs.txt: no such file; GVGAI_PCG_VGDL_GAMES must name"):
        bench_vgdlx.game_description("frogs")

    monkeypatch.delenv(bench_vgdlx.GAMES_VARIABLE)
    monkeypatch.setenv("GVGAI_PCG_CACHE", str(tmp_path / "cache"))
    urls = []

    class Reply:
        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

        def read(self):
            return b"BasicGame frogs\n"

    monkeypatch.setattr(
        bench_vgdlx.urllib.request, "urlopen", lambda url, timeout: urls.append(url) or Reply()
    )
    assert bench_vgdlx.game_description("frogs") == "BasicGame frogs\n"
    assert bench_vgdlx.game_description("frogs") == "BasicGame frogs\n"
    assert urls == [f"{bench_vgdlx.GVGAI_URL}/frogs.txt"]  # once; then from the cache
    assert bench_vgdlx.GVGAI_COMMIT in urls[0]


def test_the_level_is_our_human_level_0():
    text = bench_vgdlx.level_text("zelda")
    assert text.endswith("\n") and "A" in text and set(text.splitlines()[0]) == {"w"}


def test_ours_is_the_faster_of_one_and_two_threads_and_the_threads_are_restored(monkeypatch):
    seen = []

    def measure_ours(batch, min_seconds, game):
        seen.append(torch.get_num_threads())
        return _timed({1: 1_000, 2: 500}[torch.get_num_threads()])

    monkeypatch.setattr(bench_vgdlx, "measure_ours", measure_ours)
    monkeypatch.setattr(bench_vgdlx.os, "cpu_count", lambda: 2)
    threads = torch.get_num_threads()
    timed, best = bench_vgdlx.measure_ours_best("zelda", 64)
    assert seen == [1, 2] and best == 1 and timed.rate.median == 1_000
    assert torch.get_num_threads() == threads


@pytest.mark.slow
@pytest.mark.skipif(
    not bench_vgdlx.vgdlx_installed() or not os.environ.get(bench_vgdlx.GAMES_VARIABLE),
    reason="VGDLx or GVGAI's game descriptions (GVGAI_PCG_VGDL_GAMES) not at hand",
)
def test_vgdlx_measures_each_game():
    # A child process, as for DoorKey (JAX's absl logging and pytest's captured stderr).
    code = (
        "from gvgai_pcg.bench import vgdlx as bench_vgdlx\n"
        "for game in bench_vgdlx.GAMES:\n"
        "    t = bench_vgdlx.measure_vgdlx(game, batch=4, min_seconds=0.0)\n"
        "    print(t.rate.low, t.rate.median, t.rate.high, t.setup_s)"
    )
    child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    for line in child.stdout.splitlines()[-3:]:
        low, median, high, setup_s = map(float, line.split())
        assert 0 < low <= median <= high and setup_s > 0
