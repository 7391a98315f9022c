"""Collector workers are spawned processes, and a spawned process starts by running the parent's
main script again (as ``__mp_main__``): a script that calls ``train`` outside an
``if __name__ == "__main__":`` block would start the same training again in every worker, which
fails there (the run directory is locked, or multiprocessing refuses a process started while
bootstrapping) and left the parent waiting on workers that never answer.

So a training with ``collector.workers`` > 1 is refused in one line before anything is written,
in the parent (the call comes from the main script's top level, outside such a block) and, where
the parent could not tell (its source unreadable), in each worker while it bootstraps.
"""

from __future__ import annotations

import ast
import inspect
import multiprocessing
import sys
from pathlib import Path
from types import FrameType, ModuleType

ADVICE = (
    'put the code that calls it under `if __name__ == "__main__":` (collector workers are spawned '
    "processes, and each runs the main script again)"
)


class MissingMainGuardError(SystemExit):
    """A training with collector workers started from a script's unguarded top level: ends the
    program with one line (exit status 1), as Python ends one with an uncaught ``SystemExit``."""


def refuse_without_main_guard(what: str = "training with collector.workers > 1") -> None:
    """Raise ``MissingMainGuardError`` when ``what`` would start worker processes that run the
    main script's unguarded top level again, or when this process is such a worker."""
    if _bootstrapping():
        raise MissingMainGuardError(
            f"{what} was started again by a worker process while it ran the main script "
            f"{_script_name('__mp_main__')}: {ADVICE}"
        )
    line = _unguarded_call_line()
    if line is not None:
        raise MissingMainGuardError(
            f"{what} is started at {_script_name()}:{line} outside a main guard: {ADVICE}"
        )


def _bootstrapping() -> bool:
    """True in a spawned process while it runs the parent's main script (multiprocessing's own
    test for its "bootstrapping phase" error)."""
    return bool(getattr(multiprocessing.current_process(), "_inheriting", False))


def _main_module() -> ModuleType | None:
    return sys.modules.get("__main__")


def _script_name(module: str = "__main__") -> str:
    """The file of the main script (in a bootstrapping worker: ``__mp_main__``, its second run)."""
    return str(getattr(sys.modules.get(module), "__file__", None) or "(the main script)")


def _unguarded_call_line() -> int | None:
    """The line of the main script's top level that this call comes from, when a spawned process
    would run it again: outside an ``if __name__ == "__main__":`` block. ``None`` when it is
    guarded, when a spawned process would not run the script again (no file: ``python -c``, a
    notebook; ``python -m package``; the start method "fork"), or when its source is unreadable."""
    main = _main_module()
    path = getattr(main, "__file__", None)
    spec_name = getattr(getattr(main, "__spec__", None), "name", None) or ""
    if main is None or path is None or spec_name == "__main__" or spec_name.endswith(".__main__"):
        return None
    if multiprocessing.get_start_method(allow_none=True) == "fork":
        return None
    lines = [
        frame.f_lineno
        for frame in _frames()
        if frame.f_globals is vars(main) and frame.f_code.co_name == "<module>"
    ]
    if not lines:
        return None
    try:
        tree = ast.parse(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, SyntaxError, ValueError):
        return None
    guarded = [_body_lines(node) for node in ast.walk(tree) if _is_main_guard(node)]
    unguarded = [line for line in lines if not any(line in block for block in guarded)]
    return unguarded[0] if unguarded else None


def _body_lines(node: ast.If) -> range:
    """The lines of an ``if``'s body (its ``else`` runs in a spawned process too)."""
    return range(node.body[0].lineno, (node.body[-1].end_lineno or node.body[-1].lineno) + 1)


def _frames() -> list[FrameType]:
    frame, found = inspect.currentframe(), []
    while frame is not None:
        found.append(frame)
        frame = frame.f_back
    return found


def _is_main_guard(node: ast.AST) -> bool:
    """``if __name__ == "__main__":`` (either side first)."""
    if not isinstance(node, ast.If) or not isinstance(node.test, ast.Compare):
        return False
    test = node.test
    if len(test.ops) != 1 or not isinstance(test.ops[0], ast.Eq):
        return False
    sides = [test.left, test.comparators[0]]
    names = [side for side in sides if isinstance(side, ast.Name) and side.id == "__name__"]
    texts = [side for side in sides if isinstance(side, ast.Constant) and side.value == "__main__"]
    return len(names) == 1 and len(texts) == 1
