"""The pilot of the ``medium`` sweep: which A2C setup (envs per update, learning rate) reaches the
study's Zelda scores in the fewest core-hours.

Each pilot run is a training run directory (``config.yaml``, ``log.csv``) published under
``results/pilot/runs``, plus ``cpu.json`` beside the runs: each run's CPU seconds, measured from
``/proc`` while it trained (the machine was shared, so wall time is not a run's cost; CPU time
nearly is). Runs of other folders (the ``small`` sweep's, the setup before the pilot) come in with
their wall time as their cost: they ran one thread each, two side by side on two otherwise quiet
cores, where wall time is CPU time. The table says, per run, the frames and CPU hours it took for
its training score, averaged over a window of frames, to first reach each target. On PCG 0.5 the
training levels are drawn afresh from the d = 0.5 generator every episode, the distribution of the
d = 0.5 test set, so the training score estimates the test score there; the protocol's evaluation
of the final models confirms it.

    python -m gvgai_pcg.study.sweeps.pilot results/pilot results/small/runs/zelda-pcg0.5-*
    python -m gvgai_pcg.study.sweeps.pilot --page docs/pilot.md results/pilot results/small/runs
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path

import yaml

from gvgai_pcg.rundir.atomic_files import atomic_write_text
from gvgai_pcg.rundir.run_log import read_log

WINDOW_FRAMES = 500_000  # the training score is averaged over this many frames (about 100 episodes)


@dataclass
class PilotRun:
    name: str
    condition: str
    num_envs: int
    lr: float
    seed: int
    frames: int
    cpu_seconds: float | None
    rows: list[dict[str, float]]

    @property
    def cpu_per_frame(self) -> float | None:
        return self.cpu_seconds / self.frames if self.cpu_seconds and self.frames else None


def read_pilot(folder: Path) -> list[PilotRun]:
    """The pilot runs published in ``folder`` (``runs/*`` and ``cpu.json``)."""
    folder = Path(folder)
    cpu_path = folder / "cpu.json"
    cpu = json.loads(cpu_path.read_text()) if cpu_path.is_file() else {}
    return [read_run(run, cpu.get(run.name)) for run in sorted((folder / "runs").iterdir())]


def read_run(run: Path, cpu_seconds: float | None = None) -> PilotRun:
    """One run directory; its cost is ``cpu_seconds``, else its logged wall time."""
    config = yaml.safe_load((run / "config.yaml").read_text())
    rows = read_log(run / "log.csv")
    if cpu_seconds is None and rows:
        cpu_seconds = rows[-1]["time"]
    return PilotRun(
        run.name,
        f"{config['game']['name']}-{config['regimen']['tag']}",
        int(config["env"]["num_envs"]),
        float(config["algo"]["lr"]),
        int(config["seed"]),
        int(rows[-1]["frames"]) if rows else 0,
        cpu_seconds,
        rows,
    )


def smoothed_scores(rows: list[dict[str, float]], window: int = WINDOW_FRAMES) -> list[tuple[int, float]]:
    """``(frames, mean training score over the rows of the last window frames)`` per row, from the
    first full window on; every row is the mean of the same number of episodes."""
    out = []
    for i, row in enumerate(rows):
        if row["frames"] < window:
            continue
        inside = [r["mean_score"] for r in rows[: i + 1] if r["frames"] > row["frames"] - window]
        out.append((int(row["frames"]), sum(inside) / len(inside)))
    return out


def frames_to_reach(rows: list[dict[str, float]], target: float, window: int = WINDOW_FRAMES) -> int | None:
    """The first frame count at which the smoothed training score reaches ``target`` (None: never)."""
    return next((frames for frames, score in smoothed_scores(rows, window) if score >= target), None)


def score_at(rows: list[dict[str, float]], frames: int, window: int = WINDOW_FRAMES) -> float | None:
    """The smoothed training score at the last row at or before ``frames`` (None: not that far)."""
    before = [score for f, score in smoothed_scores(rows, window) if f <= frames]
    reached = rows and rows[-1]["frames"] >= frames - window // 10  # a last row just short counts
    return before[-1] if before and reached else None


def pilot_table(runs: list[PilotRun], targets: tuple[float, ...], at_frames: tuple[int, ...]) -> str:
    """A Markdown table: per run, the smoothed training score at ``at_frames`` and the frames and
    CPU hours to reach each of ``targets``."""
    head = ["run", "envs", "lr", "seed", "frames", "CPU ms / 1k frames"]
    head += [f"training score at {f / 1e6:g}M" for f in at_frames]
    head += [f"to {t:g}: frames (CPU h)" for t in targets]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * 2 + "---:|" * (len(head) - 2)]
    for run in runs:
        per = run.cpu_per_frame
        cells = [run.name, str(run.num_envs), f"{run.lr:g}", str(run.seed), f"{run.frames / 1e6:.1f}M"]
        cells.append(f"{per * 1e6:.0f}" if per else "-")
        for frames in at_frames:
            score = score_at(run.rows, frames)
            cells.append(f"{score:.2f}" if score is not None else "-")
        for target in targets:
            if run.condition != TARGET_CONDITION:  # the targets are scores of this condition only
                cells.append("n/a")
                continue
            reached = frames_to_reach(run.rows, target)
            if reached is None:
                cells.append("not reached")
            else:
                hours = f" ({reached * per / 3600:.2f})" if per else ""
                cells.append(f"{reached / 1e6:.2f}M{hours}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


TARGETS = (2.0, 2.5, 3.0)  # training scores on PCG 0.5 (the study's d = 0.5 test score is 3.45)
TARGET_CONDITION = "zelda-pcg0.5"
AT_FRAMES = (2_000_000, 5_000_000, 10_000_000)


START, END = "<!-- pilot:start -->", "<!-- pilot:end -->"
# what docs/pilot.md compares the pilot with: the small sweep's Zelda PCG 0.5 and PCG 1 runs
BASELINES = ("zelda-pcg0.5-tiles-compact-seed", "zelda-pcg1.0-tiles-compact-seed")


def page_table(pilot: Path, small_runs: Path) -> str:
    """The table of docs/pilot.md: the ``small`` baselines, then the pilot's runs."""
    others = sorted(run for run in Path(small_runs).iterdir() if run.name.startswith(BASELINES))
    return pilot_table([*(read_run(run) for run in others), *read_pilot(pilot)], TARGETS, AT_FRAMES)


def write_page(page: Path, table: str) -> None:
    """Put ``table`` between the page's pilot markers."""
    text = Path(page).read_text()
    head, rest = text.split(START, 1)
    atomic_write_text(Path(page), f"{head}{START}\n{table}\n{END}{rest.split(END, 1)[1]}")


def main(argv: list[str]) -> int:
    """``PILOT_FOLDER [RUN_DIR ...]``: the pilot's runs, then single runs to compare them with.
    ``--page PAGE PILOT_FOLDER SMALL_RUNS``: write the page's table."""
    if argv[:1] == ["--page"]:
        write_page(Path(argv[1]), page_table(Path(argv[2]), Path(argv[3])))
        return 0
    folder, others = (Path(argv[0]) if argv else Path("results/pilot")), [Path(a) for a in argv[1:]]
    runs = [*(read_run(run) for run in others), *read_pilot(folder)]
    print(pilot_table(runs, TARGETS, AT_FRAMES))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
