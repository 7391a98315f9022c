"""Ctrl-C (SIGINT) and SIGTERM as a request to stop at the next safe point, not a crash.

While a ``StopSignal`` is armed (the training session), either signal is only recorded; the
training loop looks at it after every update and then stops the way a finished run does (a
checkpoint, the log), so a preempted job (SLURM sends SIGTERM before it kills) or an impatient
user loses no frames. A second Ctrl-C stops at once (``KeyboardInterrupt``). Before and after
the session (imports, config, the final files) there is nothing to save: SIGINT raises
``KeyboardInterrupt`` and SIGTERM ``StoppedOutsideTraining``.

A launcher may handle signals itself. The submitit launcher (SLURM) logs and ignores SIGTERM
and, on its preemption signal (SIGUSR2 by default, SIGUSR1 if so configured), requeues the job
and exits. Its handlers are kept: SIGUSR1/SIGUSR2 are taken
over only where such a handler exists, and ``hand_over`` passes the signals received to the
launcher's handlers once the checkpoint is written (and, after a SIGTERM that it only logged,
waits a while for the follow-up signal it acts on), so a requeued job resumes where it stopped.

Collector worker processes ignore SIGINT and SIGTERM (``ignoring_stop_signals``): the terminal
and SLURM signal the whole process group, and a worker that died on its own would take the batch
in flight with it; the main process shuts the workers down when it stops.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
# A launcher's own signals (submitit: SIGUSR2, or SIGUSR1, = requeue), taken over only where the
# launcher installed a handler for them.
LAUNCHER_SIGNALS = (signal.SIGUSR1, signal.SIGUSR2)
LAUNCHER_WAIT_S = 300.0  # after a SIGTERM that the launcher only logged: how long to await its next


class StoppedOutsideTraining(BaseException):
    """SIGTERM while no training session was running: there was nothing to save."""


class StopSignal:
    """Records SIGINT/SIGTERM (and a launcher's signals) while armed; see the module docstring."""

    def __init__(self, outside_training: type[BaseException] = StoppedOutsideTraining) -> None:
        self.outside_training = outside_training  # what SIGTERM raises while not armed
        self.signals: list[int] = []  # received while armed, in order
        self.armed = False
        self._previous: dict[int, Any] = {}  # the handlers to put back
        self._launcher: dict[int, Callable[[int, Any], Any]] = {}  # a launcher's own handlers

    @property
    def received(self) -> int | None:
        """The first signal received while armed (``None``: none)."""
        return self.signals[0] if self.signals else None

    @property
    def name(self) -> str:
        return signal.Signals(self.received).name if self.received is not None else ""

    @property
    def exit_code(self) -> int:
        """The shell's code for a process ended by the signal: 130 for SIGINT, 143 for SIGTERM."""
        return 128 + int(self.received or 0)

    @property
    def installed(self) -> bool:
        return bool(self._previous)

    def _handle(self, signum: int, frame: Any) -> None:
        if not self.armed:
            handler = self._launcher.get(signum)
            if handler is not None:
                handler(signum, frame)
            elif signum == signal.SIGINT:
                raise KeyboardInterrupt
            else:
                raise self.outside_training(signum)
            return
        if signum == signal.SIGINT and signal.SIGINT in self.signals:
            raise KeyboardInterrupt  # a second Ctrl-C: stop now
        self.signals.append(signum)

    def install(self) -> StopSignal:
        """Take the signals over (in the main thread only; elsewhere a no-op)."""
        if threading.current_thread() is threading.main_thread() and not self.installed:
            for signum in (*STOP_SIGNALS, *LAUNCHER_SIGNALS):
                handler = signal.getsignal(signum)
                if callable(handler) and handler is not signal.default_int_handler:
                    self._launcher[signum] = handler
                # an ignored signal stays ignored (nohup, a script's background job: SIGINT)
                if (signum in STOP_SIGNALS and handler is not signal.SIG_IGN) or signum in self._launcher:
                    self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def uninstall(self) -> None:
        for signum, handler in self._previous.items():
            signal.signal(signum, handler)
        self._previous.clear()

    @contextlib.contextmanager
    def arming(self) -> Iterator[StopSignal]:
        """Armed for the block (installed for it too, unless already installed)."""
        installed_here = not self.installed
        self.install()
        self.armed = True
        try:
            yield self
        finally:
            self.armed = False
            if installed_here:
                self.uninstall()

    def hand_over(self, wait_s: float = LAUNCHER_WAIT_S) -> None:
        """After the stop is saved: put the handlers back and pass the signals received to the
        launcher's own handlers (submitit requeues the job and exits here); when the launcher only
        logged a SIGTERM but acts on a signal of its own, wait up to ``wait_s`` for that one."""
        self.uninstall()
        called = False
        for signum in self.signals:
            handler = self._launcher.get(signum)
            if handler is not None:
                handler(signum, None)
                called = True
        awaited = [
            signum for signum in LAUNCHER_SIGNALS if signum in self._launcher and signum not in self.signals
        ]
        if called and awaited:
            deadline = time.monotonic() + wait_s
            while time.monotonic() < deadline:  # the launcher's handler ends the process
                time.sleep(0.2)


@contextlib.contextmanager
def stop_signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM received inside the block act once it has ended, as they would have
    acted then (for the few steps that must not be cut in two: a folder's two renames). In a
    thread other than the main one, nothing changes."""
    stop = StopSignal()
    with stop.arming():
        yield
    for signum in stop.signals[:1]:
        signal.raise_signal(signum)


class ignoring_stop_signals:  # noqa: N801 (wraps a factory, like functools.partial)
    """``factory`` (picklable) that, called in another process than the one that wrapped it (a
    collector worker), first makes that process ignore SIGINT and SIGTERM."""

    def __init__(self, factory: Callable[..., Any]) -> None:
        self.factory, self.parent_pid = factory, os.getpid()

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        if os.getpid() != self.parent_pid:
            for signum in STOP_SIGNALS:
                signal.signal(signum, signal.SIG_IGN)
        return self.factory(*args, **kwargs)
