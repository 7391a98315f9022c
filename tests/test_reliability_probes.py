"""Reliability probes (issue 37): a stop of any kind keeps the run, bad input is one line before
anything is written, and the small things a new user trips on."""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
import torch

from gvgai_pcg.cli import main, say, silence_closed_streams
from gvgai_pcg.log_backends import BACKENDS
from gvgai_pcg.progress import PlainProgress
from gvgai_pcg.rundir.run_log import RunLog
from tests.waiting import PATIENCE_S

# 8 envs x 5 steps = 40 frames a batch; a row per 8 episodes of at most 10 steps
TINY = ["regimen=lv", "env.num_envs=8", "env.max_steps=10", "log.every_episodes=8", "log.curve=false"]


class ClosedPipe(io.StringIO):
    """A stream whose reader went away: every write raises BrokenPipeError."""

    def write(self, text: str) -> int:
        raise BrokenPipeError(32, "Broken pipe")

    def isatty(self) -> bool:
        return False


def _without_progress(err: str) -> str:
    """stderr but the progress lines (one every few seconds: a slow machine writes some)."""
    return "\n".join(line for line in err.strip().splitlines() if not line.startswith("train: "))


def _saved_frames(run_dir: Path) -> int:
    return int(torch.load(run_dir / "checkpoints" / "last.pt", weights_only=True)["frames"])


# --- 1. nothing lost on any stop ---


def test_a_progress_line_into_a_closed_pipe_raises_once_then_the_bar_is_silent():
    bar = PlainProgress(100, "train", "frame", stream=ClosedPipe(), interval=0.0)
    bar.update(10)  # the first update only marks where the speed is measured from
    with pytest.raises(BrokenPipeError):
        bar.update(10)
    bar.update(10)
    bar.close()  # a cleanup's close does not hide the first error behind a second


def test_say_falls_back_to_stdout_when_stderr_is_gone(monkeypatch, capsys):
    monkeypatch.setattr(sys, "stderr", ClosedPipe())
    assert say("gvgai-pcg train: one line")
    assert capsys.readouterr().out == "gvgai-pcg train: one line\n"
    monkeypatch.setattr(sys, "stdout", ClosedPipe())
    assert not say("nowhere to go")


def test_a_progress_write_into_a_closed_pipe_saves_the_run_and_exits_141(tmp_path, monkeypatch, capsys):
    """The reader of stderr went away mid-run (``gvgai-pcg train 2>&1 | head``): the last complete
    update is saved, one line goes to what still works (stdout here), and the exit is 141."""
    monkeypatch.setattr("gvgai_pcg.progress.PLAIN_INTERVAL_S", 0.0)  # a line at every update
    monkeypatch.setattr(sys, "stderr", ClosedPipe())
    argv = ["train", *TINY, "total_frames=4000", "checkpoint.every_frames=1000000"]
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, f"out_dir={tmp_path}", "run_name=run"])
    assert exit_info.value.code == 141
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1 and out[0].startswith("gvgai-pcg train: training stopped by BrokenPipeError"), out
    assert "the last complete update (80 frames) is saved in" in out[0] and "resume with: " in out[0]
    assert _saved_frames(tmp_path / "run") == 80  # the second update's line was the one that failed


def test_a_logger_backend_that_fails_mid_run_keeps_the_last_update(tmp_path, monkeypatch, capsys):
    rows = {"written": 0}
    write = RunLog.write

    def fail_on_the_second_row(self, row):
        rows["written"] += 1
        if rows["written"] == 2:
            raise RuntimeError("wandb: network unreachable")
        return write(self, row)

    monkeypatch.setattr(RunLog, "write", fail_on_the_second_row)
    argv = ["train", *TINY, "total_frames=4000", "checkpoint.every_frames=1000000"]
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, f"out_dir={tmp_path}", "run_name=run"])
    assert exit_info.value.code == 1
    err = _without_progress(capsys.readouterr().err)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert err.startswith("gvgai-pcg train: training stopped by RuntimeError: wandb: network unreachable;")
    frames = _saved_frames(tmp_path / "run")
    assert frames > 0 and f"({frames} frames) is saved in " in err
    saved = torch.load(tmp_path / "run" / "checkpoints" / "last.pt", weights_only=True)
    assert saved["log_rows"] == 1  # the row that failed is not counted
    monkeypatch.setattr(RunLog, "write", write)
    assert main([*argv[:-2], f"total_frames={frames + 40}", f"out_dir={tmp_path}", "run_name=run"]) == 0
    assert _saved_frames(tmp_path / "run") == frames + 40  # it resumes where it stopped


def test_a_failure_before_the_first_update_saves_no_checkpoint(tmp_path, monkeypatch, capsys):
    """Nothing was trained: a checkpoint of 0 frames would only make a corrected config a refusal."""
    from gvgai_pcg.rundir.run_log import EpisodeTracker

    def out_of_memory(self, rollout):
        raise RuntimeError("not enough memory")

    monkeypatch.setattr(EpisodeTracker, "update", out_of_memory)
    with pytest.raises(SystemExit) as exit_info:
        main(["train", *TINY, "total_frames=400", f"out_dir={tmp_path}", "run_name=run"])
    assert exit_info.value.code == 1
    err = _without_progress(capsys.readouterr().err)
    assert err.startswith(
        "gvgai-pcg train: training stopped by RuntimeError: not enough memory; no checkpoint"
    )
    assert not (tmp_path / "run" / "checkpoints" / "last.pt").exists()


def test_silencing_closed_streams_leaves_working_ones_alone(capsys):
    silence_closed_streams()
    print("still here")
    assert capsys.readouterr().out == "still here\n"


def _sigint_by_default() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.slow  # a real training process, Ctrl-C to its group while its pipe's reader dies: ~40 s
def test_ctrl_c_through_a_pipe_whose_reader_died_keeps_the_run(tmp_path):
    """``gvgai-pcg train 2>&1 | tee log`` and Ctrl-C: the terminal signals the whole group, tee dies
    first, the next progress write meets a closed pipe. The run is saved and exits 130."""
    overrides = [*TINY, "checkpoint.every_frames=10000000", "total_frames=10000000"]
    command = [
        sys.executable,
        "-m",
        "gvgai_pcg.cli",
        "train",
        *overrides,
        f"out_dir={tmp_path}",
        "run_name=run",
    ]
    job = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        start_new_session=True,
        preexec_fn=_sigint_by_default,  # a background job inherits SIGINT ignored
    )
    try:
        for line in job.stdout:  # up to the first progress line: training is under way
            if line.startswith(b"train: "):
                break
        assert job.poll() is None
        os.killpg(job.pid, signal.SIGINT)
        job.stdout.close()  # the reader (tee) is gone
        assert job.wait(timeout=PATIENCE_S) == 130
    finally:
        if job.poll() is None:
            os.killpg(job.pid, signal.SIGKILL)
    run_dir = tmp_path / "run"
    assert _saved_frames(run_dir) > 0
    log = (run_dir / "train.log").read_text()  # the only place left for its line
    assert "gvgai-pcg train: " in log and "SIGINT" in log and "resume with: gvgai-pcg train" in log


# --- 2. usage errors: one line, exit 2, before anything is written ---


def _one_line_refusal(argv: list[str], capsys, code: int = 2) -> str:
    with pytest.raises(SystemExit) as exit_info:
        assert main(argv) == code  # (train returns its code; the others raise it)
        raise SystemExit(code)
    assert exit_info.value.code == code
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    return err.strip()


@pytest.fixture
def no_wandb_no_tensorboard(monkeypatch):
    """As on a machine without the extras (whether or not this one has them)."""
    monkeypatch.setitem(BACKENDS, "wandb", ("gvgai_pcg_no_such_package", "wandb"))
    monkeypatch.setitem(BACKENDS, "tensorboard", ("gvgai_pcg_no_such_package", "tensorboard"))


def _choices(group: str) -> str:
    from gvgai_pcg.config import config_dir

    return ", ".join(sorted(path.stem for path in (config_dir() / group).glob("*.yaml")))


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("regimen=ppgc", f"regimen=ppgc: no such regimen; the choices are {_choices('regimen')}"),
        ("game=zeldaa", "game=zeldaa: no such game; the choices are boulderdash, frogs, solarfox, zelda"),
        ("log.backends=[csv,wandb]", "install it with: pip install 'gvgai-pcg[wandb]'"),
        ("log.backends=[tensorboard]", "install it with: pip install 'gvgai-pcg[tensorboard]'"),
    ],
)
def test_a_missing_option_or_extra_is_one_line_before_hydra_or_torch(
    override, message, tmp_path, capsys, no_wandb_no_tensorboard
):
    out = tmp_path / "runs"
    err = _one_line_refusal(["train", override, f"out_dir={out}"], capsys)
    assert err.startswith("gvgai-pcg train: error: ") and message in err
    assert not out.exists()  # no config.yaml, .hydra/, sessions.csv


def test_a_mistyped_option_in_a_sweep_is_refused_too(tmp_path, capsys):
    err = _one_line_refusal(["train", "-m", "regimen=pcg,ppgc", f"out_dir={tmp_path / 'runs'}"], capsys)
    assert "regimen=ppgc: no such regimen" in err


@pytest.mark.parametrize(
    "argv",
    [
        ["train", "game=zeldaa"],
        ["train", "-m", "regimen=pcg,ppgc"],
        ["evaluate", "--game", "zelda", "--levels", ""],
        ["analyze", "--game", "zelda", "--levels", "/nonexistent"],
    ],
    ids=["train", "train-sweep", "evaluate", "analyze"],
)
def test_the_quick_refusal_imports_neither_torch_nor_hydra(argv):
    code = (
        "import sys; from gvgai_pcg.cli import main\n"
        f"try:\n    code = main({argv!r})\nexcept SystemExit as stop:\n    code = stop.code\n"
        "print(code, 'torch' in sys.modules, 'hydra' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.stdout.split() == ["2", "False", "False"], done.stderr


def test_the_python_api_refuses_a_missing_log_extra_before_writing(tmp_path, no_wandb_no_tensorboard):
    from gvgai_pcg.config import compose_config
    from gvgai_pcg.rl import train

    cfg = compose_config([*TINY, "total_frames=40", "log.backends=[csv,wandb]", f"out_dir={tmp_path}"])
    with pytest.raises(ValueError, match=r"pip install 'gvgai-pcg\[wandb\]'"):
        train(cfg, tmp_path / "run")
    assert sorted(path.name for path in (tmp_path / "run").iterdir()) == [".lock"]  # (the lock stays)


@pytest.mark.parametrize(
    ("levels", "message"),
    [
        ("/nonexistent", "--levels /nonexistent: no such folder"),
        ("README.md", "--levels README.md: a file; expected a folder of .txt level files"),
    ],
)
def test_analyze_names_a_missing_or_wrong_levels_path_in_one_line(levels, message, tmp_path, capsys):
    err = _one_line_refusal(
        ["analyze", "--game", "zelda", "--levels", levels, "--out", str(tmp_path / "a")], capsys
    )
    assert err == f"gvgai-pcg analyze: error: {message}"
    assert not (tmp_path / "a").exists()


# --- 5. the Gymnasium entry points change no global state ---


def test_the_gymnasium_entry_points_leave_the_start_method_unset():
    code = (
        "import multiprocessing, gymnasium, gvgai_pcg\n"
        "gymnasium.make('gvgai_pcg/Zelda-v0'); import gvgai_pcg.gym.vector\n"
        "import torchrl  # (already imported: its own setting was undone)\n"
        "print(multiprocessing.get_start_method(allow_none=True))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=PATIENCE_S)
    assert done.stdout.strip() == "None", done.stderr[-2000:]


@pytest.mark.slow  # a second interpreter importing torch: several seconds
def test_a_start_method_set_by_the_user_is_kept():
    code = (
        "import multiprocessing; multiprocessing.set_start_method('forkserver')\n"
        "import gvgai_pcg.gym.adapter\n"
        "print(multiprocessing.get_start_method(allow_none=True))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=PATIENCE_S)
    assert done.stdout.strip() == "forkserver", done.stderr[-2000:]


ASYNC_WITHOUT_MAIN_GUARD = """
import gymnasium, gvgai_pcg
envs = gymnasium.make_vec("gvgai_pcg/Zelda-v0", num_envs=2, vectorization_mode="async")
observations, _ = envs.reset(seed=0)
envs.step(envs.action_space.sample())
envs.close()
print("ok", observations.shape[0])
"""


@pytest.mark.slow  # two Gymnasium worker processes, each building an env: ~20 s
def test_async_make_vec_works_in_a_script_without_a_main_guard(tmp_path):
    script = tmp_path / "script.py"
    script.write_text(ASYNC_WITHOUT_MAIN_GUARD)
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path
    )
    assert done.returncode == 0 and done.stdout.split() == ["ok", "2"], done.stderr[-3000:]


# --- 6. the small things ---


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_a_progress_line_shows_the_current_speed_and_at_most_100_percent():
    stream, clock = io.StringIO(), Clock()
    bar = PlainProgress(100, "train", "frame", stream=stream, interval=5.0, clock=clock)
    clock.now = 60.0  # a minute of imports and compilation before the first batch
    bar.update(40)
    clock.now = 65.0
    bar.update(40)  # 40 frames in the 5 s since the first batch
    clock.now = 70.0
    bar.update(40)  # past the total: a run ends a part of a batch beyond it
    bar.close()
    assert stream.getvalue().splitlines() == [
        "train: 80/100 frame (80%), 8 frame/s",
        "train: 120/100 frame (100%), 8 frame/s",
    ]


def test_a_fixed_level_run_shows_one_speed_and_no_difficulty(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr("gvgai_pcg.progress.PLAIN_INTERVAL_S", 0.0)
    argv = ["train", *TINY, "total_frames=300", f"out_dir={tmp_path}", "run_name=run"]
    assert main(argv) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("train: ")]
    assert lines and lines[-1].startswith("train: 320/300 frame (100%), ")
    for line in lines:
        assert line.count("/s") == 1 and "fps=" not in line and "d=" not in line and "nan" not in line, line
    assert any("score=" in line for line in lines)


def test_gvgai_pcg_version(capsys):
    from gvgai_pcg import __version__

    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0 and capsys.readouterr().out == f"gvgai-pcg {__version__}\n"


ROOT = Path(__file__).parents[1]


def test_the_references_cover_every_command_and_the_evaluation_api():
    from gvgai_pcg.cli import COMMANDS

    cli = (ROOT / "docs" / "reference" / "cli.md").read_text()
    assert [name for name in COMMANDS if f"| `{name}` |" not in cli] == []
    assert "## `gvgai-pcg replay`" in cli and "## `gvgai-pcg reproduce`" in cli
    assert "::: gvgai_pcg.evaluation.play_episodes" in (ROOT / "docs" / "reference" / "api.md").read_text()
    assert "GVGAI_PCG_COMPILE=0" in (ROOT / "README.md").read_text()


# --- 10, 11. a full disk, killed writers, errors that name their file, bad options ---


def test_a_full_disk_at_a_checkpoint_is_one_line_and_the_checkpoint_before_stays(
    tmp_path, monkeypatch, capsys
):
    import errno

    from gvgai_pcg.rl import run_session

    saves = {"count": 0}
    save = run_session.save_checkpoint

    def full_after_the_first(path, state):
        saves["count"] += 1
        if saves["count"] > 1:
            raise OSError(errno.ENOSPC, "No space left on device")
        return save(path, state)

    monkeypatch.setattr(run_session, "save_checkpoint", full_after_the_first)
    argv = ["train", *TINY, "total_frames=4000", "checkpoint.every_frames=40"]
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, f"out_dir={tmp_path}", "run_name=run"])
    assert exit_info.value.code == 1
    err = _without_progress(capsys.readouterr().err)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert err.startswith(
        f"gvgai-pcg train: training stopped (no space left on device: {tmp_path / 'run'}); the last "
        f"complete update could not be saved; {tmp_path / 'run' / 'checkpoints' / 'last.pt'} (40 frames) is "
        "intact; free some space first; resume with: gvgai-pcg train regimen=lv"
    ), err
    assert _saved_frames(tmp_path / "run") == 40


@pytest.mark.slow  # a real training until a 3 MB tmpfs is full (a checkpoint is 2.4 MB)
def test_training_into_a_small_tmpfs_is_one_line_and_keeps_the_checkpoint(tmp_path, capsys):
    small = tmp_path / "small"
    small.mkdir()
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=3m", "tmpfs", str(small)], capture_output=True
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.decode().strip()}")
    try:
        argv = ["train", *TINY, "total_frames=400", "checkpoint.every_frames=40"]
        with pytest.raises(SystemExit) as exit_info:
            main([*argv, f"out_dir={small}", "run_name=run"])
        assert exit_info.value.code == 1
        err = _without_progress(capsys.readouterr().err)
        assert len(err.splitlines()) == 1 and "Traceback" not in err, err
        assert f"training stopped (no space left on device: {small / 'run'}); " in err
        assert "(40 frames) is intact; free some space first; resume with: " in err
        assert _saved_frames(small / "run") == 40
        assert [p.name for p in (small / "run" / "checkpoints").iterdir()] == ["last.pt"]  # no temporary left
    finally:
        subprocess.run(["umount", "--lazy", str(small)], check=False)  # (train.log may still be open)


def test_temporary_files_of_killed_writers_are_removed_and_live_ones_kept(tmp_path):
    from gvgai_pcg.rundir.atomic_files import remove_stale_temporaries

    dead = tmp_path / f".last.pt.{2**22 + 1}.tmp"  # above Linux's largest PID: no such process
    mine, other = tmp_path / f".last.pt.{os.getpid()}.tmp", tmp_path / "notes.tmp"
    for path in (dead, mine, other):
        path.write_bytes(b"x" * 100)
    assert remove_stale_temporaries(tmp_path) == [dead]
    assert not dead.exists() and mine.exists() and other.exists()


def test_a_session_removes_what_a_killed_checkpoint_writer_left(tmp_path):
    from gvgai_pcg.rl.run_session import open_run

    stale = tmp_path / "run" / "checkpoints" / f".last.pt.{2**22 + 1}.tmp"
    stale.parent.mkdir(parents=True)
    stale.write_bytes(b"x" * 1000)
    with open_run(tmp_path / "run", {"log": {"backends": ["csv"]}}, {}):
        pass
    assert not stale.exists()


def test_a_log_that_is_not_numbers_is_named_with_its_line(tmp_path):
    from gvgai_pcg.rundir.run_log import read_log

    log = tmp_path / "log.csv"
    log.write_text("frames,episodes,mean_score\n40,8,0.5\n80,abc,0.5\n120,20,0.5\n")
    with pytest.raises(ValueError, match=rf"^{log}, line 3: episodes='abc' is not a number"):
        read_log(log)


def _usage_error(argv: list[str], capsys) -> str:
    """An argparse refusal: exit 2, the usage line and one error line."""
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    return capsys.readouterr().err


def test_a_difficulty_sweep_of_infinities_is_refused_as_such(capsys):
    err = _usage_error(["generate", "--game", "zelda", "--difficulty", "0:1:inf"], capsys)
    assert "finite number" in err and "nan" not in err


def test_generate_into_a_full_disk_leaves_no_empty_level_file(tmp_path, monkeypatch, capsys):
    import errno

    def full(self, text, *args, **kwargs):
        open(self, "w").close()  # the file is created, nothing fits
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Path, "write_text", full)
    err = _one_line_refusal(["generate", "--game", "zelda", "--out", str(tmp_path)], capsys)
    assert err == (
        f"gvgai-pcg generate: error: [Errno 28] {tmp_path / 'zelda_d1_s0.txt'} could not be written "
        "(No space left on device)"
    )
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("option", "message"),
    [
        (["--seconds", "-1"], "--seconds must be a finite number > 0, got -1.0"),
        (["--device", "tpu"], "--device 'tpu': expected cpu, cuda or cuda:N"),
        (["--batch-sizes", "0"], "--batch-sizes must be comma-separated integers >= 1, got '0'"),
    ],
)
def test_bench_refuses_bad_options_in_one_line(option, message, capsys):
    assert _one_line_refusal(["bench", *option], capsys) == f"gvgai-pcg bench: error: {message}"


def test_evaluate_refuses_empty_levels_and_keeps_a_path_with_a_comma_whole(tmp_path, capsys):
    from gvgai_pcg.commands.evaluate import _levels
    from gvgai_pcg.levels import human_level

    err = _one_line_refusal(["evaluate", "--game", "zelda", "--levels", "", "--episodes", "1"], capsys)
    assert err == (
        "gvgai-pcg evaluate: error: --levels '': no level given; expected 'human' or comma-separated "
        "names/paths"
    )
    path = tmp_path / "zelda_a,b.txt"
    path.write_text(str(human_level("zelda", 2)))
    assert [str(level) for level in _levels(str(path), "zelda")] == [str(human_level("zelda", 2))]


def test_play_without_a_terminal_is_one_line(capsys):
    err = _one_line_refusal(["play", "--game", "zelda"], capsys)  # pytest's stdin is not a terminal
    assert err.startswith("gvgai-pcg play: error: play needs a terminal, and its stdin is not one")


def test_an_out_dir_that_is_a_file_is_refused_before_hydra(tmp_path, capsys):
    path = tmp_path / "runs"
    path.write_text("not a folder")
    err = _one_line_refusal(["train", f"out_dir={path}"], capsys)
    assert err == f"gvgai-pcg train: error: out_dir={path}: a file; expected a folder for the run directories"


def test_a_gymnasium_reset_takes_level_text_and_names_a_bad_level():
    import gymnasium

    env = gymnasium.make("gvgai_pcg/Zelda-v0", render_mode="ansi")
    env.reset(seed=0, options={"level": "wwwww\nwA+gw\nwwwww\n"})
    rows = [line[:5] for line in env.render().splitlines()[:3]]  # (drawn padded to a grid)
    assert rows[0] == rows[2] == "wwwww" and rows[1][:2] == "wA" and rows[1][3:] == "gw"
    with pytest.raises(ValueError, match="level 'humans' is neither a zelda level name"):
        env.reset(options={"level": "humans"})


# --- 9. level folders and resumes ---


def _level_folder(folder: Path, count: int = 2) -> Path:
    from gvgai_pcg.levels import human_level

    folder.mkdir(parents=True, exist_ok=True)
    for index in range(count):
        (folder / f"zelda_mine{index}.txt").write_text(str(human_level("zelda", index)))
    return folder


@pytest.mark.parametrize(
    ("make_link", "what"),
    [
        (lambda link: link.symlink_to(link.name), "a symlink loop"),
        (lambda link: link.symlink_to(link.parent / "gone.txt"), "a dangling symlink"),
    ],
    ids=["loop", "dangling"],
)
def test_a_level_folder_names_an_entry_it_cannot_read(make_link, what, tmp_path):
    from gvgai_pcg.levels.sets import level_set_files, load_level_set

    folder = _level_folder(tmp_path / "mine")
    link = folder / "zelda_mine9.txt"
    make_link(link)
    for read in (level_set_files, lambda path: load_level_set("zelda", path)):
        with pytest.raises(ValueError, match=rf"^{link}: {what} \(it points to .*\); fix or remove it$"):
            read(folder)
    with pytest.raises(ValueError, match=rf"^{link}: {what}"):
        level_set_files([folder / "zelda_mine0.txt", link])  # named in a list, too


def test_a_resume_on_changed_level_files_is_refused_in_one_line(tmp_path):
    from gvgai_pcg.levels.sets import level_set_fingerprint
    from gvgai_pcg.rl.run_session import open_run
    from gvgai_pcg.rl.training import own_level_set
    from gvgai_pcg.rundir.checkpoint import CheckpointError, save_checkpoint

    folder = _level_folder(tmp_path / "mine")
    config = {
        "game": {"name": "zelda"},
        "env": {"obs": "tiles"},
        "model": {"name": "compact", "hidden": 16},
        "regimen": {"name": "levels", "path": str(folder)},
        "log": {"backends": ["csv"]},
    }
    before = own_level_set(config)
    assert before == level_set_fingerprint(folder) and own_level_set({"regimen": {"name": "pcg"}}) is None
    net = torch.nn.Linear(2, 2)
    state = {"frames": 40, "episodes": 1, "elapsed": 1.0, "model": net.state_dict(), "config": config}
    state.update(optimizer=torch.optim.SGD(net.parameters(), lr=0.1).state_dict(), level_set=before)
    save_checkpoint(tmp_path / "run" / "checkpoints" / "last.pt", state)
    with open_run(tmp_path / "run", config, {}, level_set=own_level_set(config)) as session:
        assert session.saved["frames"] == 40  # the same files: resumed

    (folder / "zelda_mine1.txt").write_text((folder / "zelda_mine0.txt").read_text())  # a level replaced
    with pytest.raises(CheckpointError) as refused:
        with open_run(tmp_path / "run", config, {"config.yaml": "new"}, level_set=own_level_set(config)):
            pass
    message = str(refused.value)
    assert "\n" not in message and f"regimen.path={str(folder)!r} changed since it was saved" in message
    assert "restore those files to resume it, or choose another out_dir/run_name" in message
    assert not (tmp_path / "run" / "config.yaml").exists()  # refused before anything is written


# --- 11. errors that name their file ---


def test_a_resume_over_a_log_that_is_not_numbers_names_it(tmp_path):
    from gvgai_pcg.rl.run_session import check_log

    log = tmp_path / "log.csv"
    log.write_text("frames,episodes,mean_score\n40,8,0.5\n80,abc,0.5\n")
    with pytest.raises(ValueError, match=rf"^{log}, line 3: episodes='abc' is not a number"):
        check_log(log, {"frames": 80, "log_rows": 2})


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("game: {name: zelda\n  bad: [\n", "line 2, column 6: expected ',' or '}', but got ':'"),
        ("!!python/object:os.system\ngame: {name: zelda}\n", "could not determine a constructor for the tag"),
        ("just a string\n", "not a config (a YAML mapping)"),
    ],
    ids=["malformed", "python-tag", "not-a-mapping"],
)
def test_a_run_config_that_is_not_a_config_is_one_line_naming_it(text, problem, tmp_path, capsys):
    from tests.evaluation.conftest import make_run

    run_dir = make_run(tmp_path / "runs", "lv0", 0)
    (run_dir / "config.yaml").write_text(text)
    for argv in (
        ["evaluate", str(run_dir), "--levels", "zelda_lvl0", "--episodes", "1"],
        ["report", str(run_dir), "--no-evaluate", "--out", str(tmp_path / "report")],
        ["replay", str(run_dir), "--level", "zelda_lvl0", "--out", str(tmp_path / "x.gif")],
    ):
        err = _one_line_refusal(argv, capsys)
        assert err.startswith(f"gvgai-pcg {argv[0]}: error: {run_dir.resolve() / 'config.yaml'}: "), err
        assert problem in err and "restore the run's config" in err
    assert not (tmp_path / "x.gif").exists()


def test_results_that_are_not_records_name_their_file_and_line_and_suggest_force(tmp_path, capsys):
    from gvgai_pcg.evaluation.evaluator import read_records
    from tests.evaluation.test_report import PROTOCOL, fake_records

    path = tmp_path / "eval" / "protocol-x.jsonl"
    path.parent.mkdir()
    good = fake_records(
        "random", {s: [0.0, 0.0] for s in ("pcg0.5", "pcg1", "lv0", "lv1", "lv2", "lv3", "lv4")}
    )
    path.write_text(json.dumps(good[0].as_dict()) + '\n{"agent": "random", "game": "zel')
    with pytest.raises(ValueError, match=rf"^{path}, line 2: not an evaluation record \(JSONDecodeError: "):
        read_records(path)
    path.write_text('["a list"]\n')
    with pytest.raises(ValueError, match="evaluate again with --force to rewrite it$"):
        read_records(path)
    assert PROTOCOL.test_levels == 2


def test_a_report_says_when_the_random_agents_cache_lacks_levels(tmp_path, caplog):
    from gvgai_pcg.evaluation.evaluator import random_results_path, write_records
    from gvgai_pcg.report.build import random_records
    from tests.evaluation.test_report import HUMAN, PROTOCOL, fake_records

    full = fake_records("random", {s: [-1.0] * 2 for s in ("pcg0.5", "pcg1", "lv0", *HUMAN)})
    path = random_results_path("zelda", PROTOCOL, tmp_path)
    write_records(path, full[:2])  # the two pcg0.5 levels only
    with caplog.at_level("WARNING"):
        records = random_records("zelda", PROTOCOL, tmp_path, False, "cpu", False, False)
    assert len(records) == 2
    assert (
        f"{path} lacks the random agent's records of pcg1 (0 of 2 levels), lv0 (0 of 1 levels)" in caplog.text
    )
    assert "the Random row is blank there (run without --no-evaluate to complete it)" in caplog.text
    caplog.clear()
    write_records(path, full)
    with caplog.at_level("WARNING"):
        assert len(random_records("zelda", PROTOCOL, tmp_path, False, "cpu", False, False)) == len(full)
    assert caplog.text == ""


@pytest.mark.parametrize("device", ["cpu"])
def test_a_million_envs_are_refused_up_front_naming_the_key_and_the_estimate(
    device, tmp_path, capsys, monkeypatch
):
    from gvgai_pcg.config import memory as memory_estimate

    monkeypatch.setattr(memory_estimate, "available_bytes", lambda: 8 * 10**9)
    out = tmp_path / "runs"
    err = _one_line_refusal(["train", "env.num_envs=1000000", f"out_dir={out}"], capsys)
    assert err.startswith("gvgai-pcg train: error: env.num_envs=1000000: the run needs at least "), err
    assert (
        "GB of memory (" in err
        and "per env: its observations, the rollout and the model's activations)" in err
    )
    assert "more than the 8.0 GB available; lower env.num_envs (about " in err
    assert not out.exists()
    fit = int(err.rsplit("(about ", 1)[1].split(" ")[0])
    config = {
        "game": {"name": "zelda"},
        "env": {"num_envs": fit, "obs": "tiles"},
        "model": {"name": "compact", "hidden": 256},
        "algo": {"n_steps": 5},
    }
    memory_estimate.check_memory(config)  # as many as it says fit: accepted
    config["env"]["num_envs"] = fit + 1000
    with pytest.raises(ValueError, match="env.num_envs="):
        memory_estimate.check_memory(config)


@pytest.mark.parametrize(
    "argv",
    [["hydra.mode=MULTIRUN", "env.num_envs=-1,1"], ["-m", "hydra.job.chdir=false", "env.num_envs=1,-1"]],
    ids=["hydra.mode", "hydra.job"],
)
def test_hydra_overrides_do_not_skip_the_config_check(argv, tmp_path, capsys):
    sweep = tmp_path / "sweep"
    err = _one_line_refusal(["train", *argv, f"hydra.sweep.dir={sweep}", f"out_dir={tmp_path}"], capsys)
    assert err == "gvgai-pcg train: error: env.num_envs=-1: expected an integer >= 1"
    assert not sweep.exists()  # no job of the sweep started


def test_a_report_over_a_log_that_is_not_numbers_names_it(tmp_path):
    from gvgai_pcg.evaluation.evaluator import run_results_path, write_records
    from gvgai_pcg.report import build_report
    from tests.evaluation.conftest import make_run, write_log
    from tests.evaluation.test_report import HUMAN, PROTOCOL, fake_records

    run_dir = make_run(tmp_path / "runs", "lv0", 0)
    model = str((run_dir / "model.pt").resolve())
    scores = {s: [1.0, 1.0] for s in ("pcg0.5", "pcg1", "lv0", *HUMAN)}
    write_records(run_results_path(run_dir, PROTOCOL), fake_records(str(run_dir), scores, 1000, model))
    write_log(run_dir, [(100, 0.5, 0.0), (200, 0.5, 0.0)])
    log = run_dir / "log.csv"
    log.write_text(log.read_text().replace(",0.5,", ",abc,", 1))
    with pytest.raises(ValueError, match=rf"^{log.resolve()}, line 2: mean_score='abc' is not a number"):
        build_report([tmp_path / "runs"], tmp_path / "out", PROTOCOL, tmp_path / "cache", evaluate=False)


def test_a_truncated_published_json_names_its_file(tmp_path, capsys):
    from tests.evaluation.conftest import make_run

    run_dir = make_run(tmp_path / "runs", "lv0", 0)
    (run_dir / "published.json").write_text('{"checkpoint": "runs/x/model.pt", "fra')
    err = _one_line_refusal(["report", str(run_dir), "--no-evaluate", "--out", str(tmp_path / "out")], capsys)
    assert err.startswith(
        f"gvgai-pcg report: error: {run_dir.resolve() / 'published.json'}: not a published run's"
    )
    assert err.endswith("restore it, or remove that run's folder to publish the run again")


@pytest.mark.slow  # two short trainings
def test_a_run_on_a_level_folder_refuses_to_resume_on_changed_files(tmp_path, capsys):
    folder = _level_folder(tmp_path / "mine")
    argv = [
        "train",
        *TINY[1:],
        "regimen=levels",
        f"regimen.path={folder}",
        f"out_dir={tmp_path}",
        "run_name=run",
    ]
    assert main([*argv, "total_frames=40"]) == 0
    saved = torch.load(tmp_path / "run" / "checkpoints" / "last.pt", weights_only=True)
    from gvgai_pcg.levels.sets import level_set_fingerprint

    assert saved["level_set"] == level_set_fingerprint(folder)
    capsys.readouterr()
    (folder / "zelda_mine1.txt").write_text((folder / "zelda_mine0.txt").read_text())
    err = _one_line_refusal([*argv, "total_frames=80"], capsys)
    assert (
        err.startswith("gvgai-pcg train: error: the run directory ") and "changed since it was saved" in err
    )
    assert _saved_frames(tmp_path / "run") == 40


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (["report", "RUNS", "--no-evaluate", "--out", "FILE"], "--out"),
        (["report", "RUNS", "--no-evaluate", "--cache-dir", "FILE"], "--cache-dir"),
        (["analyze", "--game", "zelda", "--out", "FILE"], "--out"),
        (["evaluate", "--game", "zelda", "--cache-dir", "FILE"], "--cache-dir"),
        (["reproduce", "--budget", "smoke", "--no-train", "--publish", "FILE"], "--publish"),
    ],
)
def test_a_file_where_a_folder_goes_is_one_line_naming_the_flag(argv, flag, tmp_path, capsys):
    from gvgai_pcg.cli import main

    afile = tmp_path / "afile"
    afile.write_text("")
    runs = tmp_path / "runs"
    runs.mkdir()
    argv = [str(afile) if a == "FILE" else str(runs) if a == "RUNS" else a for a in argv]
    with pytest.raises(SystemExit) as stopped:
        main(argv)
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert f"error: {flag} {afile}: a file; expected a folder" in err and len(err.strip().splitlines()) == 1
    assert afile.read_text() == "" and list(runs.iterdir()) == []


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["bench", "--output", "DIR", "--seconds", "0.1"],
            "--output DIR: a folder; expected a file to write",
        ),
        (
            ["bench", "--output", "DIR/none/bench.md"],
            "--output DIR/none/bench.md: no folder DIR/none to write it in",
        ),
        (["replay", "RUN", "--level", "zelda_lvl0", "--out", "DIR"], "--out DIR: a folder; expected a file"),
        (
            ["replay", "RUN", "--level", "zelda_lvl0", "--out", "DIR/a.png"],
            "--out DIR/a.png: expected a .gif file",
        ),
    ],
)
def test_a_folder_where_a_file_goes_is_one_line_before_any_work(argv, message, tmp_path, capsys):
    from gvgai_pcg.cli import main
    from tests.evaluation.conftest import make_run

    run = make_run(tmp_path / "runs", "lv0", 0)
    argv = [a.replace("DIR", str(tmp_path)).replace("RUN", str(run)) for a in argv]
    with pytest.raises(SystemExit) as stopped:
        main(argv)
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert message.replace("DIR", str(tmp_path)) in err and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["runs"]
