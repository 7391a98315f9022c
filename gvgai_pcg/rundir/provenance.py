"""Which code trained a run: one row per training session in the run's ``sessions.csv``.

A run trained over several sittings may be continued by newer code (a resumed run picks up
whatever checkout resumes it), and a published table should say which commits its numbers come
from. ``train`` appends a row when a session is accepted, before its first frame.
"""

from __future__ import annotations

import csv
import datetime
import platform
import subprocess
from pathlib import Path

import torch

SESSIONS_NAME = "sessions.csv"
FIELDS = ("started", "commit", "frames", "machine", "torch", "threads")


def code_commit() -> str:
    """The short commit of the checkout holding this package, with ``+dirty`` when its tracked
    code or configs differ from it; ``unknown`` outside a git checkout (an install in a
    ``.venv`` inside one included)."""
    where = Path(__file__).parent

    def git(*arguments: str) -> str:
        found = subprocess.run(["git", *arguments], cwd=where, capture_output=True, text=True, check=True)
        return found.stdout.strip()

    try:
        git("ls-files", "--error-unmatch", Path(__file__).name)  # this file is the checkout's own
        commit = git("rev-parse", "--short", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no", "--", ":/gvgai_pcg", ":/conf")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return commit + ("+dirty" if dirty else "")


def record_session(run_dir: Path, frames: int) -> None:
    """Append this session's row (start time, commit, the frames it starts from) to the run's
    ``sessions.csv``."""
    path = run_dir / SESSIONS_NAME
    new = not path.is_file()
    row = {
        "started": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "commit": code_commit(),
        "frames": frames,
        "machine": f"{platform.machine()} {platform.system()}",
        "torch": torch.__version__,
        "threads": torch.get_num_threads(),
    }
    with open(path, "a", newline="") as file:
        writer = csv.DictWriter(file, FIELDS)
        if new:
            writer.writeheader()
        writer.writerow(row)


def session_commits(run_dir: Path) -> list[str]:
    """The commits that trained ``run_dir``, in the order they first trained it (empty when the
    run predates ``sessions.csv``)."""
    path = run_dir / SESSIONS_NAME
    if not path.is_file():
        return []
    with open(path, newline="") as file:
        commits = [row["commit"] for row in csv.DictReader(file)]
    return list(dict.fromkeys(commits))
