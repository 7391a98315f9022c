"""The protocol evaluation of one agent: every test set of a game in ONE batched env, one record
per (agent, test set, level), stored as JSON lines.

A trained run's records go to ``<run>/eval/protocol-<key>.jsonl`` (``key`` names the protocol
settings) and are reused while the run's checkpoint and frame count are unchanged; the random
agent's go to a cache per game and protocol (``<cache>/random/<game>-<key>.jsonl``), since every
report of a game needs the same baseline. One process at a time evaluates into a run's ``eval/``
or a cache file (``gvgai_pcg.rundir.run_lock``); a second is refused, naming the first, and every file
is replaced atomically.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import RunInfo
from gvgai_pcg.evaluation.max_score import level_max_score
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.evaluation.protocol import EvalSet, Protocol, protocol_test_sets, training_test_set
from gvgai_pcg.evaluation.random_agent import RandomAgent
from gvgai_pcg.evaluation.runner import Policy, play_episodes
from gvgai_pcg.games import get_game
from gvgai_pcg.rundir.atomic_files import atomic_write_text
from gvgai_pcg.rundir.run_lock import FolderLock

EVAL_DIR = "eval"


@dataclass
class LevelRecord:
    """One JSON line: what an agent did on one level of one test set."""

    agent: str  # "random", the run directory, or a published run's folder name
    game: str
    test_set: str  # pcg0.5, pcg1, lv0 … lv4; train (the run's own training levels)
    level: str
    level_seed: int | None
    episodes: int
    scores: list[float]
    lengths: list[int]
    wins: list[bool]
    max_score: int
    protocol: dict = field(default_factory=dict)
    frames: int = 0
    checkpoint: str = ""

    @property
    def mean_score(self) -> float:
        return sum(self.scores) / len(self.scores)

    def as_dict(self) -> dict:
        return {**asdict(self), "mean_score": self.mean_score, "win_rate": sum(self.wins) / len(self.wins)}

    @classmethod
    def from_dict(cls, data: dict) -> LevelRecord:
        names = cls.__dataclass_fields__
        return cls(**{k: v for k, v in data.items() if k in names})


def evaluate_policy(
    game: str,
    policy: Policy,
    protocol: Protocol,
    agent: str,
    obs: str = "tiles",
    device: str = "cpu",
    progress: bool = True,
    extra_sets: Sequence[EvalSet] = (),
) -> list[LevelRecord]:
    """Play every (test set, level, episode) of the protocol, and of ``extra_sets``, at once; one
    record per level."""
    sets = [*protocol_test_sets(game, protocol), *extra_sets]
    batch = [level for s in sets for level in s.levels for _ in range(s.episodes)]
    label = f"{game} {Path(agent).name}"  # the run (or "random") the progress line belongs to
    results = play_episodes(
        game, batch, policy, protocol.max_steps, protocol.seed, obs, device, progress, label
    )
    records, start = [], 0
    for s in sets:
        for level in s.levels:
            part = slice(start, start + s.episodes)
            start += s.episodes
            records.append(
                LevelRecord(
                    agent=agent,
                    game=game,
                    test_set=s.name,
                    level=level.name or "",
                    level_seed=level.seed,
                    episodes=s.episodes,
                    scores=[float(v) for v in results.scores[part].tolist()],
                    lengths=[int(v) for v in results.lengths[part].tolist()],
                    wins=[bool(v) for v in results.wins[part].tolist()],
                    max_score=level_max_score(level),
                    protocol=protocol.as_dict(),
                )
            )
    return records


def write_records(path: Path, records: list[LevelRecord]) -> Path:
    """Write ``records`` as JSON lines (atomically: a temporary file renamed over ``path``)."""
    return atomic_write_text(path, "".join(json.dumps(r.as_dict()) + "\n" for r in records))


def writer_lock(folder: Path, what: str, lock_name: str | None = None):
    """The lock that makes this process the only one writing ``what`` into ``folder``."""
    purpose = f"two processes writing {what} at once would overwrite each other's"
    return FolderLock(folder, purpose, "run the other command once it is done", lock_name=lock_name)


def read_records(path: Path) -> list[LevelRecord]:
    """The records of a results file; a line that is not a record is a ``ValueError`` naming the
    file and line (``--force`` evaluates again and rewrites it)."""
    records = []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip():
            continue
        try:
            records.append(LevelRecord.from_dict(json.loads(line)))
        except (ValueError, KeyError, TypeError, AttributeError) as error:
            raise ValueError(
                f"{path}, line {number}: not an evaluation record ({type(error).__name__}: {error}); "
                "evaluate again with --force to rewrite it"
            ) from None
    return records


def run_results_path(run_dir: Path, protocol: Protocol) -> Path:
    return Path(run_dir) / EVAL_DIR / f"protocol-{protocol.key}.jsonl"


def default_cache_dir() -> Path:
    return Path(os.environ.get("GVGAI_PCG_CACHE", Path.home() / ".cache" / "gvgai-pcg"))


def random_results_path(game: str, protocol: Protocol, cache_dir: Path | None = None) -> Path:
    return (cache_dir or default_cache_dir()) / "random" / f"{game}-{protocol.key}.jsonl"


def records_are_current(records: list[LevelRecord], info: RunInfo) -> bool:
    """Whether ``records`` were made from the run's present model (its checkpoint and frames)."""
    return bool(records) and all(
        r.frames == info.frames and r.checkpoint == str(info.checkpoint) for r in records
    )


def evaluate_run(
    info: RunInfo,
    protocol: Protocol,
    device: str = "cpu",
    progress: bool = True,
    force: bool = False,
    path: Path | None = None,
) -> list[LevelRecord]:
    """The protocol's records of a trained run, from its results file when they are current;
    ``path``: another results file than the run's (a snapshot's, ``gvgai_pcg.evaluation.held_out``)."""
    path = path or run_results_path(info.path, protocol)
    if path.is_file() and not force:
        records = read_records(path)
        if records_are_current(records, info):
            return records
    policy = load_policy(info, greedy=protocol.greedy, seed=protocol.seed, device=device)
    own = (
        training_test_set(info.training_levels(protocol.test_levels), protocol)
        if info.has_training_set
        else None
    )
    with writer_lock(path.parent, f"the evaluation results of {info.path}"):
        records = evaluate_policy(
            info.game, policy, protocol, info.agent, info.obs, device, progress, [own] if own else []
        )
        for record in records:
            record.frames, record.checkpoint = info.frames, str(info.checkpoint)
        write_records(path, records)
    return records


def evaluate_random(
    game: str,
    protocol: Protocol,
    cache_dir: Path | None = None,
    device: str = "cpu",
    progress: bool = True,
    force: bool = False,
) -> list[LevelRecord]:
    """The random agent's records for ``game`` under ``protocol``, cached."""
    path = random_results_path(game, protocol, cache_dir)
    if path.is_file() and not force:
        return read_records(path)
    agent = RandomAgent(get_game(game).num_actions, seed=protocol.seed, device=device)
    with writer_lock(path.parent, f"the random agent's cache {path.name}", lock_name=f".{path.name}.lock"):
        records = evaluate_policy(game, agent, protocol, "random", "tiles", device, progress)
        write_records(path, records)
    return records
