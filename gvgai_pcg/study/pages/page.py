"""The results page: the published tables, curves, claims and runs, written into a Markdown page.

``docs/results.md`` has a block between ``<!-- results:start -->`` and ``<!-- results:end -->``
that this module rewrites from a published folder (``gvgai_pcg.study.sweeps.publish.publish``), so the
page says exactly what the data under ``results/`` says, and which runs it holds.
"""

from __future__ import annotations

import json
import os
import platform
import re
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import read_run_config
from gvgai_pcg.rundir.atomic_files import atomic_copy, atomic_write_text
from gvgai_pcg.rundir.provenance import session_commits
from gvgai_pcg.rundir.run_log import read_log

START, END = "<!-- results:start -->", "<!-- results:end -->"


def _runs_table(published: Path, target_frames: int) -> str:
    lines = [
        "| run | frames evaluated | finished | training wall time so far (h) | last logged mean score "
        "| trained at |",
        "|---|---:|---|---:|---:|---|",
    ]
    total = 0.0
    for run in sorted((published / "runs").iterdir()):
        if not (run / "published.json").is_file():
            continue
        frames = json.loads((run / "published.json").read_text())["frames"]
        rows = read_log(run / "log.csv") if (run / "log.csv").is_file() else []
        hours = rows[-1]["time"] / 3600 if rows else 0.0
        total += hours
        score = f"{rows[-1]['mean_score']:.2f}" if rows else "-"
        target = int((read_run_config(run) or {}).get("total_frames", target_frames))
        done = "yes" if frames >= target else "no (resumes)"
        commits = ", ".join(f"`{commit}`" for commit in session_commits(run)) or "-"
        lines.append(f"| {run.name} | {frames:,} | {done} | {hours:.2f} | {score} | {commits} |")
    count = len(lines) - 2
    lines += ["", f"Training time of these {count} runs: {total:.2f} run-hours (their wall times summed)."]
    return "\n".join(lines)


def results_block(published: Path, images: Path, image_prefix: str, target_frames: int, commit: str) -> str:
    """The page's results block from ``published``; the curve images are copied into ``images``
    and referenced as ``image_prefix/<name>``."""
    report = (published / "report" / "results.md").read_text()
    images.mkdir(parents=True, exist_ok=True)
    for stale in images.glob("curves-*.png"):  # a game no longer in the report keeps no figure
        stale.unlink()
    for figure in sorted((published / "report").glob("curves-*.png")):
        atomic_copy(figure, images / figure.name)
    report = re.sub(r"\]\((curves-[\w-]+\.(?:png|svg))\)", rf"]({image_prefix}/\1)", report)
    report = report.replace("# Results\n", "", 1).replace("\n## ", "\n### ")
    claims_path = published / "report" / "claims.md"
    claims = claims_path.read_text() if claims_path.is_file() else "No claims evaluated yet.\n"
    machine = f"{platform.machine()} Linux, {os.cpu_count()} cores, torch CPU, one torch thread per run"
    return "\n".join(
        [
            START,
            f"Data: `{published}` (commit `{commit}` of the code that evaluated it, and trained every run "
            f"whose own record below names no other; {machine}).",
            "",
            "### Runs",
            "",
            _runs_table(published, target_frames),
            "",
            "### The study's claims on these runs",
            "",
            claims.strip(),
            "",
            "### Tables and curves",
            "",
            "Each row is a condition at the frames its runs had when they were evaluated (a run that has not",
            "finished is evaluated at its last checkpoint and says so by its frame count).",
            report.strip(),
            END,
        ]
    )


def page_images(page: Path) -> tuple[Path, str]:
    """The folder of ``page``'s figures and the prefix its links use: ``images/<page's stem>``
    beside it (``docs/results.md``: ``docs/images/results``), so two budgets' pages keep their own."""
    return page.parent / "images" / page.stem, f"images/{page.stem}"


def write_results_page(
    page: Path, published: Path, images: Path, image_prefix: str, target_frames: int, commit: str
) -> Path:
    """Rewrite the results block of ``page`` from ``published``."""
    block = results_block(published, images, image_prefix, target_frames, commit)
    return replace_block(page, block, START, END)


def replace_block(page: Path, block: str, start: str = START, end: str = END) -> Path:
    """Replace ``page``'s text from ``start`` to ``end`` by ``block`` (which holds both markers)."""
    text = page.read_text()
    if start not in text or end not in text:
        raise ValueError(f"{page}: no {start} ... {end} block to write the results into")
    before, rest = text.split(start, 1)
    after = rest.split(end, 1)[1]
    atomic_write_text(page, before + block + after)
    return page
