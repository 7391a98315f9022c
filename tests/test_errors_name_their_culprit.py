"""Bad files and settings are refused in one line that names the culprit: a file of a run that is
not what training writes, a path that is not a model, a setting too large to play, a full disk.
Nothing is left half-written."""

from __future__ import annotations

import contextlib
import resource
import signal
from collections.abc import Iterator

import pytest
import torch

from gvgai_pcg.evaluation.ued import UEDProtocol
from gvgai_pcg.study import BUDGETS
from gvgai_pcg.study.pipeline import reproduce
from gvgai_pcg.study.sweeps.borrowed_runs import borrow_run
from tests.evaluation.conftest import make_run, write_log
from tests.evaluation.test_held_out import with_snapshots
from tests.evaluation.test_model_checks import _one_line_error as one_line_error

LEVEL = ["--levels", "zelda_lvl0", "--episodes", "1", "--max-steps", "5", "--no-progress"]


@contextlib.contextmanager
def full_disk(limit: int = 64) -> Iterator[None]:
    """Files of this process stop growing at ``limit`` bytes (EFBIG), as on a full disk."""
    old_limit = resource.getrlimit(resource.RLIMIT_FSIZE)
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # an error, not a killed process
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, old_limit[1]))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, old_limit)
        signal.signal(signal.SIGXFSZ, old_handler)


def test_a_snapshot_with_another_name_is_named(tmp_path, capsys):
    run = with_snapshots(tmp_path, frames=(500, 1000))
    (run / "snapshots" / "model-abc.pt").write_bytes((run / "model.pt").read_bytes())
    err = one_line_error(["evaluate", str(run), "--snapshots", "--no-progress"], capsys)
    assert f"{run.resolve() / 'snapshots' / 'model-abc.pt'}: not a snapshot's name" in err


def test_a_model_whose_frames_are_not_a_number_is_named(tmp_path, capsys):
    run = make_run(tmp_path / "runs", "lv0", seed=0)
    saved = torch.load(run / "model.pt", weights_only=True)
    torch.save({**saved, "frames": "abc"}, run / "model.pt")
    err = one_line_error(["evaluate", str(run), *LEVEL], capsys)
    assert f"{run.resolve() / 'model.pt'}: its 'frames' entry is 'abc'" in err


def test_a_borrowed_runs_damaged_log_is_named_and_leaves_no_half_run(tmp_path):
    source = make_run(tmp_path / "long" / "runs", "lv0", seed=0)
    write_log(source, [(500, 0.5, 0.0)])
    with open(source / "log.csv", "a") as log:
        log.write("abc,8,0.5\n")
    target = tmp_path / "short" / "runs" / source.name
    with pytest.raises(ValueError, match=r"log\.csv: line 3: frames 'abc' is not a whole number") as error:
        borrow_run(source, source / "model.pt", 1000, target)
    assert str(source / "log.csv") in str(error.value)
    assert not target.exists() and not list(target.parent.glob(".borrowing-*"))


def test_a_full_disk_during_publish_is_one_line_naming_a_file(tmp_path):
    from gvgai_pcg.study.sweeps.publish import publish

    out = tmp_path / "out"
    (out / "report").mkdir(parents=True)
    (out / "report" / "table.md").write_text("x" * 10_000)
    with full_disk(), pytest.raises(OSError) as error:
        publish(out, tmp_path / "published", None, [])
    text = str(error.value)
    assert "\n" not in text and "[(" not in text and "table.md could not be copied from " in text
    assert not (tmp_path / "published" / "report").exists()


def test_finished_only_with_nothing_finished_names_the_folder(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(FileNotFoundError) as error:
        reproduce(BUDGETS["smoke"], ["zelda-lv0"], out, train=False, progress=False, finished_only=True)
    assert str(error.value).endswith(f" under {out / 'runs'}") and "that finished" in str(error.value)


@pytest.mark.parametrize("kind", ["device", "folder"])
def test_a_model_path_that_is_not_a_file_says_what_it_is(tmp_path, capsys, kind):
    run = make_run(tmp_path / "runs", "lv0", seed=0)
    path, says = ("/dev/null", "not a regular file") if kind == "device" else (str(tmp_path), "a folder")
    err = one_line_error(["evaluate", str(run), "--model", path, *LEVEL], capsys)
    assert f"{path}: {says}" in err and "no such" not in err


def test_too_many_ued_episodes_are_refused_before_any_level_is_made(tmp_path, capsys):
    with pytest.raises(ValueError, match="1,000,000,000 episodes, more than"):
        UEDProtocol(levels=1000, seeds=1_000_000)
    argv = ["evaluate", "--game", "zelda", "--ued", "--ued-seeds", "1000000", "--cache-dir", str(tmp_path)]
    err = one_line_error(argv, capsys)
    assert "invalid UED protocol setting: levels x seeds = 1000 x 1000000" in err
    assert not list(tmp_path.iterdir())


def test_json_on_a_full_disk_leaves_no_empty_file(tmp_path, capsys):
    target = tmp_path / "scores.json"
    argv = ["evaluate", "--game", "zelda", *LEVEL, "--json", str(target)]
    with full_disk():
        err = one_line_error(argv, capsys)
    assert "File too large" in err and not target.exists()
    assert not [p for p in tmp_path.iterdir()]  # nor a temporary file


@pytest.mark.parametrize(
    ("flags", "says"),
    [
        (["--snapshots", "--every", "-1000"], "--every -1000: expected a positive number of frames"),
        (["--snapshots", "--every", "0"], "--every 0: expected a positive number of frames"),
        (["--every", "1000", *LEVEL], "--every picks snapshots to evaluate; it needs --snapshots"),
        (["--snapshots", "--every", "1000000"], "one snapshot per 1,000,000 frames picks none of its 2"),
    ],
)
def test_every_is_checked_and_a_period_that_picks_nothing_says_so(tmp_path, capsys, flags, says):
    run = with_snapshots(tmp_path, frames=(500, 1000))
    err = one_line_error(["evaluate", str(run), *flags, "--no-progress"], capsys)
    assert says in err


@pytest.mark.parametrize(
    "flag",
    [["--test-sets", "large"], ["--test-levels", "3"], ["--test-episodes", "2"], ["--human-episodes", "5"]],
)
def test_ued_refuses_the_study_protocols_settings_it_would_ignore(tmp_path, capsys, flag):
    argv = ["evaluate", "--game", "zelda", "--ued", *flag, "--cache-dir", str(tmp_path / "cache")]
    err = one_line_error(argv, capsys)
    assert f"{flag[0]}: settings of the study's protocol, which --ued does not play" in err
    assert not (tmp_path / "cache").exists()
