"""The peers beside our benchmark: tables built from fake rates (no JAX needed), the line that
says how to install the extra, and, only where the extra is installed, one real measurement of
each peer (its numbers are for `make bench`, never asserted)."""

import argparse
import subprocess
import sys

import pytest

from gvgai_pcg.bench import peers as bench_peers
from gvgai_pcg.bench import vgdlx as bench_vgdlx
from gvgai_pcg.bench.targets import Check, Section
from gvgai_pcg.bench.throughput import Rate
from gvgai_pcg.commands import bench


def _timed(median: float, setup_s: float = 0.0) -> bench_peers.Timed:
    return bench_peers.Timed(Rate(median, median / 2, median * 2), setup_s, cores=1.0, resets=3)


def test_the_peer_table_has_a_row_per_batch_size_with_the_ratio_ours_over_the_peer():
    rows = [
        bench_peers.PeerRow(64, _timed(20_000), _timed(160_000, setup_s=12.3), _timed(40_000, setup_s=4.5)),
        bench_peers.PeerRow(4096, _timed(400_000), _timed(800_000), _timed(1_000_000)),
    ]
    lines = bench_peers.peer_lines(rows, griddly=_timed(40_000), load="load average 1.0, 2.0, 3.0")
    header = next(line for line in lines if line.startswith("| B |"))
    table = [line for line in lines if line.startswith("| ") and line[2].isdigit()]
    assert [line.count("|") for line in table] == [header.count("|")] * 2
    assert table[0] == (
        "| 64 | 20,000 (10,000) | 160,000 (80,000) | 0.12x | 40,000 (20,000) | 0.50x "
        "| 1.0, 1.0, 1.0 | 12.3, 4.5 |"
    )
    assert "| 0.50x |" in table[1] and "| 0.40x |" in table[1]
    assert "load average 1.0, 2.0, 3.0" in "\n".join(lines)
    assert lines[-1].endswith("Ours / Griddly: 0.50x at B = 64, 10.00x at B = 4096.")


def test_the_peer_targets_are_zelda_at_64_against_the_bare_step_and_at_4096_against_griddly():
    rows = [
        bench_peers.PeerRow(64, _timed(20_000), _timed(10_000), _timed(40_000)),
        bench_peers.PeerRow(4096, _timed(500_000), _timed(1), _timed(1)),
    ]
    bare, griddly = bench_peers.peer_checks(rows, griddly=_timed(40_000))
    assert (bare.measured, bare.met) == (0.5, False)  # against the bare step, not the auto-reset one
    assert (griddly.measured, griddly.met) == (12.5, True)
    bare, griddly = bench_peers.peer_checks(rows[1:], griddly=None)
    assert bare.met is None and griddly.met is None


def test_without_griddly_the_table_says_so():
    rows = [bench_peers.PeerRow(8, _timed(1_000), _timed(2_000), _timed(3_000))]
    lines = bench_peers.peer_lines(rows, griddly=None, load="load average 0.0, 0.0, 0.0")
    assert lines[-1].startswith("Griddly not installed")


def test_without_the_extra_the_section_says_how_to_install_it(monkeypatch):
    monkeypatch.setattr(bench_peers, "missing_peers", lambda: ["jax", "xminigrid"])
    section = bench_peers.peers_report((64,), min_seconds=0.0)
    assert "peers not installed: pip install -e '.[peers]'" in section.text
    assert [check.met for check in section.checks] == [None, None]


def _args(**overrides) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    bench.add_arguments(parser)
    flags = [f"--{k.replace('_', '-')}" + ("" if v is True else f"={v}") for k, v in overrides.items()]
    return parser.parse_args(flags)


def test_the_bench_command_adds_peers_and_jobs_on_the_cpu_and_ends_with_every_target(monkeypatch, capsys):
    env = Section("ours\n", [Check("env", 1.5, 2.0)])
    monkeypatch.setattr(bench, "run_benchmarks", lambda **kwargs: env)
    monkeypatch.setattr(bench_peers, "missing_peers", lambda: ["jax"])
    monkeypatch.setattr(bench_vgdlx, "vgdlx_installed", lambda: False)
    jobs = Section("jobs\n", [Check("job", 30.0, 40.0, unit="s", at_most=True)])
    monkeypatch.setattr(bench, "jobs_section", lambda: jobs)  # the name the command calls
    monkeypatch.setattr(bench, "generic_section", lambda *args: Section("generic\n"))
    assert bench.run(_args(games="zelda", obs="tiles", batch_sizes="4", device="cpu")) == 0
    out = capsys.readouterr().out
    assert bench_peers.NOT_INSTALLED in out and bench_vgdlx.NOT_INSTALLED in out and "jobs\n" in out
    assert out.index("ours") < out.index(bench_peers.NOT_INSTALLED) < out.index("generic") < out.index("jobs")
    assert out.index("jobs") < out.index("| env |")
    assert "| env | at least 1.50x | 2.00x | met |" in out
    assert "| job | at most 30.0 s | 40.0 s | missed |" in out
    assert (
        "| zelda tiles at B = 64 / DoorKey-8x8 bare step at B = 64 | at least 1.00x | - | not measured |"
        in out
    )
    assert "| zelda tiles at B = 4,096 / VGDLx | at least 20.00x | - | not measured |" in out
    frogs = bench._peers(_args(games="frogs", obs="tiles", device="cpu"), "cpu")
    assert bench_peers.NOT_INSTALLED not in frogs.text and bench_vgdlx.NOT_INSTALLED in frogs.text
    assert {check.what for check in frogs.checks} == {
        "frogs tiles at B = 64 / VGDLx",
        "frogs tiles at B = 4,096 / VGDLx",
    }
    for args in (
        _args(games="zelda", obs="pixels", device="cpu"),
        _args(games="zelda", obs="tiles", device="cuda"),
        _args(games="zelda", obs="tiles", no_peers=True),
    ):
        assert bench._peers(args, args.device or "cpu") == Section()
    assert bench._jobs(_args(device="cuda"), "cuda") == Section()


@pytest.mark.skipif(bool(bench_peers.missing_peers()), reason="the peers extra is not installed")
@pytest.mark.parametrize("auto_reset", [True, False])
def test_doorkey_is_measured_when_the_extra_is_installed(auto_reset):
    # In a child process: JAX's absl logging keeps a handler on this process's captured stderr,
    # and the Hydra app of a later test (tests/test_cli_errors.py) failed on it once it was closed.
    code = (
        "from gvgai_pcg.bench import peers as bench_peers\n"
        f"t = bench_peers.measure_doorkey(batch=4, min_seconds=0.0, auto_reset={auto_reset})\n"
        "print(t.rate.low, t.rate.median, t.rate.high, t.setup_s)"
    )
    child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    low, median, high, setup_s = map(float, child.stdout.split()[-4:])
    assert 0 < low <= median <= high and setup_s > 0


def test_griddly_zelda_loads_our_human_levels_and_steps():
    pytest.importorskip("griddly")
    timed = bench_peers.measure_griddly(min_seconds=0.0)
    assert 0 < timed.rate.low <= timed.rate.median <= timed.rate.high
