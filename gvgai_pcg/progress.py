"""Progress that suits where it goes: a tqdm bar on a terminal, plain lines in a log.

On a terminal (stderr is a TTY) a bar redraws in place. Redirected to a file or a pipe
(``gvgai-pcg report > log 2>&1``, a SLURM job's output) a bar's carriage-return updates would
fill the log, so progress is one plain line at most every ``PLAIN_INTERVAL_S`` seconds, and a
last line at the end when any was written. Every command that shows progress (train, evaluate,
report, bench) goes through ``progress`` or ``track``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Iterator
from typing import IO, Protocol, TypeVar

PLAIN_INTERVAL_S = 5.0
T = TypeVar("T")


class Progress(Protocol):
    """What the callers use of a bar (tqdm's names)."""

    def update(self, n: int = 1) -> None: ...

    def set_postfix(self, **values: object) -> None: ...

    def close(self) -> None: ...


class NoProgress:
    """Shows nothing (progress turned off)."""

    def update(self, n: int = 1) -> None:
        pass

    def set_postfix(self, **values: object) -> None:
        pass

    def close(self) -> None:
        pass


class PlainProgress:
    """``desc: 12,800/1,000,000 frame (1%), 2,345 frame/s, score=0.12`` lines, one at most every
    ``interval`` seconds, and one at ``close`` if any line was written before (and the count has
    moved since).

    The speed is the current one: over the units since the previous line (for the first line,
    since the first ``update``: what came before it is start-up, imports and compilation). The
    percentage stops at 100% (a run may end a part of a batch past its total). A line that cannot
    be written (the reader of a pipe went away, a full disk) raises once; the bar then writes
    nothing more, so that its ``close`` in a cleanup does not hide the first error behind a second.
    """

    def __init__(
        self,
        total: int | None,
        desc: str,
        unit: str,
        initial: int = 0,
        stream: IO[str] | None = None,
        interval: float = PLAIN_INTERVAL_S,
        clock=time.monotonic,
    ) -> None:
        self.total, self.desc, self.unit, self.count = total, desc, unit, initial
        self.stream, self.interval, self.clock = stream, interval, clock
        self.start = self.last = clock()
        self.postfix = ""
        self.lines, self.written = 0, initial
        self.closed = self.failed = False
        self.mark: tuple[float, int] | None = None  # (time, count) the next line's speed is over

    def update(self, n: int = 1) -> None:
        self.count += n
        now = self.clock()
        if self.mark is None:
            self.mark = (now, self.count)
        elif now - self.last >= self.interval:
            self._write()

    def set_postfix(self, **values: object) -> None:
        self.postfix = " ".join(f"{key}={value}" for key, value in values.items())

    def close(self) -> None:
        if not self.closed and self.lines and self.count != self.written:
            self._write()
        self.closed = True

    def _write(self) -> None:
        if self.failed:
            return
        now = self.clock()
        done = f"{self.count:,}"
        if self.total:
            done += f"/{self.total:,} {self.unit} ({min(100.0, 100 * self.count / self.total):.0f}%)"
        else:
            done += f" {self.unit}"
        parts = [f"{self.desc}: {done}" if self.desc else done]
        since, counted = self.mark or (self.start, self.written)
        if self.count > counted and now > since:
            parts.append(f"{(self.count - counted) / (now - since):,.0f} {self.unit}/s")
        if self.postfix:
            parts.append(self.postfix)
        try:
            print(", ".join(parts), file=self.stream or sys.stderr, flush=True)
        except (OSError, ValueError):
            self.failed = True
            raise
        self.last, self.lines, self.written = now, self.lines + 1, self.count
        self.mark = (now, self.count)


def is_terminal(stream: IO[str] | None = None) -> bool:
    stream = stream or sys.stderr
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False


def progress(
    total: int | None = None,
    desc: str = "",
    unit: str = "it",
    initial: int = 0,
    enabled: bool = True,
    leave: bool = True,
    stream: IO[str] | None = None,
) -> Progress:
    """A progress display of ``total`` ``unit``s on ``stream`` (default stderr): a tqdm bar on a
    terminal, plain lines elsewhere, nothing when not ``enabled``."""
    if not enabled:
        return NoProgress()
    if is_terminal(stream):
        from tqdm.auto import tqdm

        return tqdm(
            total=total,
            desc=desc or None,
            unit=unit,
            initial=initial,
            leave=leave,
            file=stream,
            dynamic_ncols=True,
        )
    return PlainProgress(total, desc, unit, initial, stream, interval=PLAIN_INTERVAL_S)


def track(
    items: Iterable[T], desc: str = "", unit: str = "it", enabled: bool = True, total: int | None = None
) -> Iterator[T]:
    """Iterate ``items`` with a ``progress`` display of them."""
    if total is None and hasattr(items, "__len__"):
        total = len(items)  # type: ignore[arg-type]
    bar = progress(total, desc, unit, enabled=enabled)
    try:
        for item in items:
            yield item
            bar.update(1)
    finally:
        bar.close()
