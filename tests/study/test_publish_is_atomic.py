"""A publish cut short leaves the published folder as it was: each run, and the report, is built
beside its place and swapped in; a signal waits for the swap; a SIGKILL's leftovers are repaired."""

from __future__ import annotations

import json
import os
import signal
import sys
from pathlib import Path

import pytest

from gvgai_pcg.evaluation.checkpoints import find_runs
from gvgai_pcg.rundir.atomic_files import recover_folders, staging_folder
from gvgai_pcg.rundir.stop_signal import stop_signals_deferred
from gvgai_pcg.study.sweeps import publish as publishing
from tests.evaluation.conftest import make_run, write_log


def _contents(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _published_once(tmp_path: Path) -> tuple[Path, Path, Path]:
    out, dest = tmp_path / "out", tmp_path / "published"
    run = make_run(out / "runs", "lv0", 0)
    write_log(run, [(500, 1.0, 0.0), (1000, 2.0, 0.0)])
    (out / "report").mkdir(parents=True)
    (out / "report" / "results.md").write_text("# Results\n\nfirst\n")
    publishing.publish(out, dest)
    return out, dest, run


def test_a_publish_interrupted_while_staging_a_run_leaves_the_published_run_as_it_was(tmp_path, monkeypatch):
    out, dest, run = _published_once(tmp_path)
    before = _contents(dest)
    write_log(run, [(500, 1.0, 0.0), (1000, 3.0, 0.0)])  # the run has something new to publish

    def cut_short(run, staged, *args):
        (staged / "log.csv").write_text("frames\n")  # half of the new publication is written
        raise KeyboardInterrupt

    monkeypatch.setattr(publishing, "_stage_run", cut_short)
    with pytest.raises(KeyboardInterrupt):
        publishing.publish(out, dest)
    assert _contents(dest) == before
    assert [p.name for p in (dest / "runs").iterdir()] == [run.name]  # no staging folder left


def test_a_publish_interrupted_while_copying_the_report_keeps_the_old_report(tmp_path, monkeypatch):
    out, dest, _ = _published_once(tmp_path)
    (out / "report" / "results.md").write_text("# Results\n\nsecond\n")
    real_copytree = publishing.shutil.copytree

    def copy_then_stop(source, target, *args, **kwargs):
        real_copytree(source, target, *args, **kwargs)
        if Path(source) == out / "report":
            raise KeyboardInterrupt

    monkeypatch.setattr(publishing.shutil, "copytree", copy_then_stop)
    with pytest.raises(KeyboardInterrupt):
        publishing.publish(out, dest)
    assert (dest / "report" / "results.md").read_text() == "# Results\n\nfirst\n"
    assert not staging_folder(dest / "report").exists()


def test_a_second_publish_replaces_the_run_and_the_report_and_keeps_no_stale_figure(tmp_path):
    out, dest, run = _published_once(tmp_path)
    (dest / "report" / "curves-frogs.png").write_bytes(b"an earlier report's figure")
    write_log(run, [(500, 1.0, 0.0), (1000, 3.0, 0.0)])
    (out / "report" / "results.md").write_text("# Results\n\nsecond\n")
    publishing.publish(out, dest)
    assert (dest / "runs" / run.name / "log.csv").read_bytes() == (run / "log.csv").read_bytes()
    assert json.loads((dest / "runs" / run.name / "published.json").read_text())["frames"] == 1000
    assert sorted(p.name for p in (dest / "report").iterdir()) == ["results.md"]
    assert sorted(p.name for p in dest.iterdir()) == ["report", "runs"]


def test_what_a_sigkill_between_the_two_renames_leaves_is_repaired_by_the_next_publish(tmp_path):
    out, dest, run = _published_once(tmp_path)
    published = dest / "runs" / run.name
    before = _contents(published)
    published.rename(published.with_name(f".replaced-{run.name}"))  # the old run moved aside, then killed
    stale = staging_folder(dest / "report")
    stale.mkdir()  # and a staging folder that never got swapped in
    assert find_runs([dest / "runs"]) == []  # hidden folders are no runs
    recover_folders(dest / "runs")
    recover_folders(dest)
    assert _contents(published) == before and not stale.exists()
    assert find_runs([dest / "runs"]) == [published.resolve()]


def test_a_moved_aside_folder_whose_replacement_arrived_is_removed(tmp_path):
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "new").write_text("new")
    (tmp_path / ".replaced-run").mkdir()
    recover_folders(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"] and (tmp_path / "run" / "new").is_file()


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_a_signal_inside_the_deferred_block_acts_only_when_the_block_has_ended():
    steps = []

    def on_term(signum, frame):
        steps.append("handled")

    previous = signal.signal(signal.SIGTERM, on_term)
    try:
        with stop_signals_deferred():
            os.kill(os.getpid(), signal.SIGTERM)
            steps.append("after the kill, still inside")
        steps.append("after the block")
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert steps == ["after the kill, still inside", "handled", "after the block"]
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # xdist's workers ignore it
    try:
        with pytest.raises(KeyboardInterrupt):
            with stop_signals_deferred():
                os.kill(os.getpid(), signal.SIGINT)
                steps.append("Ctrl-C waited too")
    finally:
        signal.signal(signal.SIGINT, previous)
    assert steps[-1] == "Ctrl-C waited too"


def test_an_atomic_copy_keeps_the_times_and_leaves_no_temporary_file(tmp_path):
    from gvgai_pcg.rundir.atomic_files import atomic_copy

    source = tmp_path / "records.jsonl"
    source.write_text("{}\n")
    os.utime(source, (1_000_000, 1_000_000))
    target = atomic_copy(source, tmp_path / "random" / "records.jsonl")
    assert target.read_text() == "{}\n" and target.stat().st_mtime == 1_000_000
    assert [p.name for p in target.parent.iterdir()] == ["records.jsonl"]
