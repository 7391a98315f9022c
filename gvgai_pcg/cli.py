"""``gvgai-pcg``: one console script, one subcommand per module in ``gvgai_pcg.commands``.

Each command module exposes ``add_arguments(parser)`` and ``run(args) -> int``, so a command
lives next to nothing but its own options; this file only dispatches. ``train`` is a Hydra app
and takes Hydra's own arguments, so it is handed the raw argument list; its refusals end the same
way as every other command's (one line, exit 2), also when they are raised inside the Hydra app.

Imports: the package imports at the top of its modules, with one measured exception. A command's
quick paths (``--help``, a usage error, a refused option) load neither torch nor Hydra, so each
command module imports at its top only what is torch-free, and imports the rest (``gvgai_pcg.rl``,
``evaluation``, ``study``, ``play``, Hydra) inside ``run``: importing them takes seconds, some
twenty times the half second that ``gvgai-pcg evaluate --help`` takes without them
(``python -X importtime``). For the same reason ``config`` reads the learners' and models'
registries, and the built-in curricula build their level sources, inside functions.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import sys
from collections.abc import Callable

COMMANDS: dict[str, str] = {
    "evaluate": "Evaluate agents (random or trained) on human levels and test sets",
    "bench": "Measure engine throughput and write docs/benchmarks.md",
    "generate": "Generate levels at a difficulty",
    "play": "Play a level in the terminal",
    "train": "Train an agent (Hydra app: gvgai-pcg train game=zelda regimen=ppcg ...)",
    "report": "Merge run results into the results table and figures",
    "analyze": "Level-distribution analysis (PCA + DBSCAN)",
    "replay": "Render an episode of a trained agent as an animated GIF",
    "reproduce": "The study from sweep to Table 1: train, evaluate, report (--budget smoke|small|medium|...)",
    "vgdl": "GVGAI's VGDL games: list them, inspect one's parse in Java's orders and its plan",
}
RAW_ARGUMENT_COMMANDS = {"train"}
# What a command raises for bad input (a malformed level file is a ValueError naming its file,
# line and column): one line on stderr, not a traceback. GVGAI_PCG_DEBUG=1 shows the traceback.
USER_ERRORS = (ValueError, OSError, OverflowError)


def _command_module(name: str):
    return importlib.import_module(f"gvgai_pcg.commands.{name}")


def available_commands() -> dict[str, str]:
    """The commands whose module is installed (a command may be added by a later release)."""
    found = {}
    for name, help_text in COMMANDS.items():
        if importlib.util.find_spec(f"gvgai_pcg.commands.{name}") is not None:
            found[name] = help_text
    return found


def version() -> str:
    """The installed distribution's version (the package's own where it is not installed)."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as installed_version

    try:
        return installed_version("gvgai-pcg")
    except PackageNotFoundError:
        from gvgai_pcg import __version__

        return __version__


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    commands = available_commands()
    if argv and argv[0] in RAW_ARGUMENT_COMMANDS and argv[0] in commands:
        name, rest = argv[0], argv[1:]
        return run_reporting_errors(name, lambda: _command_module(name).run_raw(rest))
    parser = argparse.ArgumentParser(
        prog="gvgai-pcg", description="Batched GVGAI games, level generators, training and evaluation."
    )
    parser.add_argument("--version", action="version", version=f"gvgai-pcg {version()}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    # Only the chosen command's module is imported (they pull in torch, hydra, ...); a bare
    # `gvgai-pcg` or an unknown command lists them all without importing any.
    chosen = argv[0] if argv and argv[0] in commands else None
    for name, help_text in commands.items():
        sub_parser = sub.add_parser(name, help=help_text, description=help_text)
        if name == chosen and name not in RAW_ARGUMENT_COMMANDS:
            _command_module(name).add_arguments(sub_parser)
    args = parser.parse_args(argv)
    return run_reporting_errors(args.command, lambda: _command_module(args.command).run(args))


def run_reporting_errors(name: str, command: Callable[[], int | None]) -> int:
    """Run ``command``; a ``USER_ERRORS`` exception ends it with one line on stderr and exit 2, an
    interrupt (Ctrl-C) with one line and exit 130. However it ends, a stream whose reader went away
    is pointed at /dev/null, so that Python's flush at exit adds no second error."""
    try:
        return int(command() or 0)
    except BrokenPipeError:  # the reader went away (`gvgai-pcg generate ... | head`): not an error
        return 0
    except USER_ERRORS as error:
        if os.environ.get("GVGAI_PCG_DEBUG"):
            raise
        say(f"gvgai-pcg {name}: error: {error}")
        raise SystemExit(2) from None
    except KeyboardInterrupt:
        if os.environ.get("GVGAI_PCG_DEBUG"):
            raise
        say(f"gvgai-pcg {name}: interrupted")
        raise SystemExit(130) from None
    finally:
        silence_closed_streams()


def say(line: str) -> bool:
    """Write ``line`` to stderr, or to stdout when stderr cannot be written (its reader went away,
    a full disk under it); ``False`` when neither could take it."""
    for stream in (sys.stderr, sys.stdout):
        try:
            stream.write(line + "\n")
            stream.flush()
            return True
        except (OSError, ValueError, AttributeError):  # a closed pipe or file; no stream at all
            continue
    return False


def silence_closed_streams() -> None:
    """Point stdout and stderr at /dev/null where they can no longer be written, so that what is
    left in their buffers does not fail again at exit ("Exception ignored ... BrokenPipeError")."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            try:
                os.dup2(os.open(os.devnull, os.O_WRONLY), stream.fileno())
            except (OSError, ValueError):
                pass


if __name__ == "__main__":
    sys.exit(main())
