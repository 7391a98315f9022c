"""Progress: a tqdm bar on a terminal, a plain line at most every few seconds in a log."""

from __future__ import annotations

import io
import subprocess
import sys

from gvgai_pcg.progress import PLAIN_INTERVAL_S, NoProgress, PlainProgress, progress, track


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_log_gets_a_line_at_most_every_interval_and_one_at_the_end():
    stream, clock = io.StringIO(), Clock()
    bar = PlainProgress(1000, "train", "frame", stream=stream, clock=clock)
    step = PLAIN_INTERVAL_S / 4
    for _ in range(10):  # 2.5 intervals
        clock.now += step
        bar.update(100)
        bar.set_postfix(score="0.50")
    bar.close()
    lines = stream.getvalue().splitlines()
    assert "\r" not in stream.getvalue()
    rate = f"{100 / step:,.0f} frame/s"
    assert lines == [
        f"train: 400/1,000 frame (40%), {rate}, score=0.50",
        f"train: 800/1,000 frame (80%), {rate}, score=0.50",
        f"train: 1,000/1,000 frame (100%), {rate}, score=0.50",
    ]


def test_a_short_task_writes_nothing_to_a_log():
    stream = io.StringIO()
    bar = progress(10, "short", "step", stream=stream)
    assert isinstance(bar, PlainProgress)
    bar.update(10)
    bar.close()
    assert stream.getvalue() == ""


def test_a_terminal_gets_a_tqdm_bar_and_off_is_silent():
    from tqdm import tqdm

    assert isinstance(progress(10, "x", stream=Terminal()), tqdm)
    assert isinstance(progress(10, "x", enabled=False, stream=Terminal()), NoProgress)
    assert list(track(range(3), "items", enabled=False)) == [0, 1, 2]


def test_an_evaluation_redirected_to_a_file_has_no_carriage_returns(tmp_path):
    # `gvgai-pcg report > log 2>&1` shows the same display while it evaluates
    command = [
        sys.executable,
        "-m",
        "gvgai_pcg.cli",
        "evaluate",
        "--agent",
        "random",
        "--game",
        "frogs",
        "--protocol",
        "--test-levels",
        "1",
        "--human-episodes",
        "1",
        "--max-steps",
        "30",
        "--cache-dir",
        str(tmp_path),
    ]
    log = tmp_path / "log"
    with open(log, "w") as handle:
        subprocess.run(command, stdout=handle, stderr=subprocess.STDOUT, check=True, timeout=300)
    assert "\r" not in log.read_text() and "random agent" in log.read_text()
