"""``gvgai-pcg play`` driven through a pseudo terminal: keys in, the screen read back.

The play command runs in a child process on a pty under TERM=xterm; a small screen model below
replays the bytes curses writes (cursor moves, erases, repeats) into a grid of characters, so
the test reads the screen as a person would see it.
"""

from __future__ import annotations

import curses
import os
import pty
import re
import select
import struct
import subprocess
import sys
import termios
import time
from fcntl import ioctl
from pathlib import Path

import numpy as np
import pytest

from gvgai_pcg.levels import human_level
from gvgai_pcg.play import PlaySession
from gvgai_pcg.play.terminal import screen_lines

ROWS, COLS = 30, 90
CSI = re.compile(rb"\x1b\[([?>=]?)([0-9;]*)([@-~])")


class Screen:
    """A minimal xterm model: enough of ECMA-48 for what ncurses emits to draw text."""

    def __init__(self, rows: int, cols: int) -> None:
        self.rows, self.cols = rows, cols
        self.grid = [[" "] * cols for _ in range(rows)]
        self.y = self.x = 0
        self.last = " "

    def feed(self, data: bytes) -> None:
        i = 0
        while i < len(data):
            byte = data[i : i + 1]
            if byte == b"\x1b":
                match = CSI.match(data, i)
                if match:
                    self._csi(match.group(1), match.group(2), match.group(3).decode())
                    i = match.end()
                    continue
                i += 3 if data[i + 1 : i + 2] in (b"(", b")") else 2  # charset / keypad / other escapes
                continue
            if byte == b"\r":
                self.x = 0
            elif byte == b"\n":
                self.y = min(self.y + 1, self.rows - 1)
            elif byte == b"\b":
                self.x = max(self.x - 1, 0)
            elif 32 <= data[i] < 127:
                self._put(byte.decode())
            i += 1

    def _put(self, char: str) -> None:
        if self.x < self.cols:
            self.grid[self.y][self.x] = char
        self.x = min(self.x + 1, self.cols - 1)
        self.last = char

    def _csi(self, private: bytes, params: bytes, final: str) -> None:
        if private:
            return  # modes (?1049h, ?25l ...): nothing to draw
        numbers = [int(p) if p else 0 for p in params.split(b";")] if params else []
        n = numbers[0] if numbers and numbers[0] > 0 else 1
        if final in "Hf":
            row = numbers[0] if numbers and numbers[0] else 1
            col = numbers[1] if len(numbers) > 1 and numbers[1] else 1
            self.y, self.x = row - 1, col - 1
        elif final == "d":
            self.y = n - 1
        elif final == "G":
            self.x = n - 1
        elif final == "A":
            self.y = max(self.y - n, 0)
        elif final == "B":
            self.y = min(self.y + n, self.rows - 1)
        elif final == "C":
            self.x = min(self.x + n, self.cols - 1)
        elif final == "D":
            self.x = max(self.x - n, 0)
        elif final == "b":
            for _ in range(n):
                self._put(self.last)
        elif final == "X":
            self.grid[self.y][self.x : self.x + n] = [" "] * len(self.grid[self.y][self.x : self.x + n])
        elif final == "K":
            mode = numbers[0] if numbers else 0
            start, end = {0: (self.x, self.cols), 1: (0, self.x + 1), 2: (0, self.cols)}[mode]
            self.grid[self.y][start:end] = [" "] * (end - start)
        elif final == "J":
            mode = numbers[0] if numbers else 0
            if mode in (2, 3):
                self.grid = [[" "] * self.cols for _ in range(self.rows)]
            elif mode == 0:
                self.grid[self.y][self.x :] = [" "] * (self.cols - self.x)
                for row in range(self.y + 1, self.rows):
                    self.grid[row] = [" "] * self.cols

    def text(self) -> str:
        return "\n".join("".join(row).rstrip() for row in self.grid)


class Terminal:
    """A child process on a pty of ROWS x COLS, with the screen it draws."""

    def __init__(self, argv: list[str]) -> None:
        self.master, slave = pty.openpty()
        ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", ROWS, COLS, 0, 0))
        env = {**os.environ, "TERM": "xterm", "ESCDELAY": "25"}
        env.pop("LINES", None), env.pop("COLUMNS", None)
        self.process = subprocess.Popen(
            argv, stdin=slave, stdout=slave, stderr=slave, env=env, start_new_session=True
        )
        os.close(slave)
        self.screen = Screen(ROWS, COLS)
        self.raw = b""

    def read_until(self, pattern: str, timeout: float = 60.0) -> str:
        """The screen once ``pattern`` is on it and the child has stopped drawing."""
        deadline = time.monotonic() + timeout
        while not re.search(pattern, self.screen.text()):
            if time.monotonic() > deadline:
                raise AssertionError(f"{pattern!r} never appeared; screen:\n{self.screen.text()}")
            self._read(0.1)
        while self._read(0.3):
            pass
        return self.screen.text()

    def _read(self, wait: float) -> bool:
        ready, _, _ = select.select([self.master], [], [], wait)
        if not ready:
            return False
        try:
            chunk = os.read(self.master, 65536)
        except OSError:  # the child closed the pty
            return False
        self.raw += chunk
        self.screen.feed(chunk)
        return bool(chunk)

    def send(self, keys: bytes) -> None:
        os.write(self.master, keys)

    def close(self) -> int:
        try:
            return self.process.wait(timeout=20)
        finally:
            os.close(self.master)


def xterm_key(capability: str) -> bytes:
    """The bytes xterm sends for a key while curses has keypad mode on (e.g. kcuf1: b"\\x1bOC")."""
    curses.setupterm("xterm", sys.__stdout__.fileno() if sys.__stdout__ else 1)
    return curses.tigetstr(capability)


def avatar_position(screen: str) -> tuple[int, int]:
    rows = screen.splitlines()
    hits = [(r, c) for r, row in enumerate(rows) for c, ch in enumerate(row) if ch == "A"]
    assert len(hits) == 1, f"expected one avatar on screen:\n{screen}"
    return hits[0]


@pytest.fixture
def play_zelda():
    terminal = Terminal(
        [sys.executable, "-m", "gvgai_pcg.cli", "play", "--game", "zelda", "--level", "zelda_lvl0"]
    )
    yield terminal
    if terminal.process.poll() is None:
        terminal.process.kill()
        terminal.process.wait()


def test_arrow_keys_move_the_avatar_and_q_quits(play_zelda: Terminal) -> None:
    screen = play_zelda.read_until(r"tick 0 ")
    assert "zelda zelda_lvl0" in screen and "q quit" in screen
    start = avatar_position(screen)
    right = xterm_key("kcuf1")
    for tick in (1, 2, 3):
        play_zelda.send(right)
        screen = play_zelda.read_until(rf"tick {tick} ")
    row, col = avatar_position(screen)
    assert row == start[0] and col > start[1]  # zelda_lvl0's avatar walks right along the top corridor
    play_zelda.send(xterm_key("kcud1"))
    screen = play_zelda.read_until(r"tick 4 ")
    play_zelda.send(b"q")
    play_zelda.read_until(r"zelda zelda_lvl0: playing, score 0, tick 4")  # the summary left on exit
    assert play_zelda.close() == 0


def test_pixels_render_writes_a_png_on_a_key_press(tmp_path: Path) -> None:
    png = tmp_path / "frame.png"
    argv = [sys.executable, "-m", "gvgai_pcg.cli", "play", "--game", "frogs", "--difficulty", "0.5"]
    terminal = Terminal([*argv, "--seed", "3", "--render", "pixels", "--png", str(png)])
    try:
        terminal.read_until(r"tick 0 ")
        assert not png.exists()
        terminal.send(b".")
        terminal.read_until(r"frame written to")
        terminal.send(b"q")
        assert terminal.close() == 0
    finally:
        if terminal.process.poll() is None:
            terminal.process.kill()
    from matplotlib.image import imread

    assert imread(png).shape[:2] == (110, 280)


def test_session_shows_the_level_and_ends_the_episode() -> None:
    session = PlaySession(human_level("zelda", 0), seed=0, max_steps=3)
    lines = screen_lines(session)
    assert lines[3] == "#############" and "A" in lines[4]
    for _ in range(5):
        session.act("NIL")
    assert session.tick == 3 and session.outcome == "out of time"
    session.restart()
    assert session.tick == 0 and session.outcome == "playing"
    with pytest.raises(ValueError, match="its actions are"):
        PlaySession(human_level("frogs", 0)).act("USE")
    assert isinstance(session.frame(), np.ndarray)
