"""The curses front end of ``gvgai-pcg play``: keys in, the frame, tick and score out.

Turn-based by default (every key is one tick, as if the game waited for you); with ``fps`` > 0
the game ticks on its own and a tick without a key is NIL, as in GVGAI's real-time play.
"""

from __future__ import annotations

import curses
from pathlib import Path

from gvgai_pcg.play.session import PlaySession

KEYS = {
    curses.KEY_LEFT: "LEFT",
    curses.KEY_RIGHT: "RIGHT",
    curses.KEY_UP: "UP",
    curses.KEY_DOWN: "DOWN",
    ord("a"): "LEFT",
    ord("d"): "RIGHT",
    ord("w"): "UP",
    ord("s"): "DOWN",
    ord(" "): "USE",
    ord("."): "NIL",
}
QUIT_KEYS = {ord("q"), ord("Q")}
RESTART_KEYS = {ord("r"), ord("R")}


def help_line(session: PlaySession) -> str:
    use = "  space USE" if "USE" in session.actions else ""
    return f"arrows/wasd move{use}  . wait  r restart  q quit"


def screen_lines(session: PlaySession, message: str = "") -> list[str]:
    """Everything on screen, top to bottom."""
    status = f"tick {session.tick}  score {session.score:g}  {session.outcome}"
    lines = [f"gvgai-pcg play: {session.level.game} {session.level.name or ''}".rstrip(), status, ""]
    lines += session.rows()
    lines += ["", help_line(session)]
    if message:
        lines.append(message)
    return lines


def draw(screen: curses.window, lines: list[str]) -> None:
    screen.erase()
    height, width = screen.getmaxyx()
    for y, line in enumerate(lines[: height - 1]):
        screen.addstr(y, 0, line[: width - 1])
    screen.refresh()


def play(session: PlaySession, png_path: Path | None = None, fps: float = 0.0) -> None:
    """Run the game loop until q; with ``png_path``, every key press rewrites that PNG."""
    curses.wrapper(_loop, session, png_path, fps)


def _loop(screen: curses.window, session: PlaySession, png_path: Path | None, fps: float) -> None:
    try:
        curses.curs_set(0)
    except curses.error:
        pass  # a terminal that cannot hide its cursor still plays
    screen.keypad(True)
    screen.timeout(int(1000 / fps) if fps > 0 else -1)
    message = ""
    while True:
        draw(screen, screen_lines(session, message))
        key = screen.getch()
        if key in QUIT_KEYS:
            return
        if key in RESTART_KEYS:
            session.restart()
        elif key == -1:
            session.act("NIL")  # real time: nothing pressed this tick
        elif KEYS.get(key) in session.actions:
            session.act(KEYS[key])
        if png_path is not None and key != -1:
            session.save_png(png_path)
            message = f"frame written to {png_path}"
