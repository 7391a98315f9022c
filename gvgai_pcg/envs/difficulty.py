"""``DifficultyTransform``: the one difficulty that PCG X and Progressive PCG train at.

The transform owns the curriculum so the env stays stateless about it: before a reset it writes
the current difficulty into the reset tensordict (the env's level source generates at it), and
after each step it moves the difficulty once per finished episode, in order of env index:
+alpha on a win, -alpha on a loss, clipped to [0, 1] after every move (GENERATORS.md §2). The
value lives in a shared-memory tensor, so collector workers in other processes read and move
one difficulty, and it is a buffer, so ``state_dict()`` carries it into checkpoints. Processes
that share it through files (``share_through``) also share a lock file, so that two workers'
moves never overwrite each other. It travels as float64 from here to the level source, which
generates at exactly that value.
"""

from __future__ import annotations

from pathlib import Path

import torch
from tensordict import TensorDictBase
from torchrl.envs.transforms import Transform

from gvgai_pcg.envs.shared_buffers import exclusive, share_buffers_through
from gvgai_pcg.games.registry import get_game_spec

MODES = ("fixed", "progressive")
# Each move rounds d to this many decimals: a sum of steps (0.07 + 0.01 = 0.08000000000000002)
# stays the d a log shows and a level name records, whatever alpha (1e-5 moves as well).
DECIMALS = 10
WIN_RULES = ("game", "study")


class DifficultyTransform(Transform):
    """Owns the difficulty of generated levels.

    Args:
        mode: ``"fixed"`` (PCG X: always ``start``) or ``"progressive"`` (PPCG).
        alpha: the step per finished episode (0.01 in the study).
        start: the initial difficulty (0 for PPCG, X for PCG X).
        win_rule: ``"game"`` (the game's own win flag) or ``"study"`` (anything but a loss is a
            win, so a step-limit timeout raises d; a game whose ``GameSpec.study_score_win``
            is set counts an episode score of at least that instead: Boulderdash 20).
        game: the game name, needed by the study's win rule (which differs by game).
    """

    def __init__(
        self,
        mode: str = "progressive",
        alpha: float = 0.01,
        start: float = 0.0,
        win_rule: str = "game",
        game: str | None = None,
    ) -> None:
        mode = "progressive" if mode == "ppcg" else mode
        if mode not in MODES:
            raise ValueError(f"unknown difficulty mode {mode!r}; valid modes are: {', '.join(MODES)}")
        if win_rule not in WIN_RULES:
            raise ValueError(f"unknown win rule {win_rule!r}; valid rules are: {', '.join(WIN_RULES)}")
        if not 0.0 <= start <= 1.0:
            raise ValueError(f"start difficulty must be in [0, 1], got {start}")
        if not alpha >= 0.0:
            raise ValueError(f"alpha must be >= 0, got {alpha}")
        if win_rule == "study" and game is None:
            raise ValueError("the study's win rule differs by game: give game= (e.g. game='zelda')")
        super().__init__(in_keys=[], out_keys=["difficulty"])
        self.mode, self.alpha, self.win_rule, self.game = mode, float(alpha), win_rule, game
        self.register_buffer(
            "shared_difficulty", torch.tensor([float(start)], dtype=torch.float64).share_memory_()
        )
        self.register_buffer("episodes", torch.zeros(1, dtype=torch.int64).share_memory_())
        self.lock_path: Path | None = None  # a file every process that moves the difficulty locks

    @property
    def difficulty(self) -> float:
        return float(self.shared_difficulty[0])

    def share_through(self, directory: Path) -> None:
        """Back the difficulty by memory-mapped files in ``directory``, so that collector worker
        processes (which receive a pickled copy of this transform) read and move the very same
        value as the main process; in-process shared memory does not survive that pickling. The
        files start from the current values (a resumed run's are restored first), and a lock file
        there serialises the moves of all processes."""
        share_buffers_through(self, directory)
        self.lock_path = directory / "difficulty.lock"

    def wins(self, next_tensordict: TensorDictBase) -> torch.Tensor:
        """``[B]`` bool: which of this step's envs won, under the chosen rule."""
        won = next_tensordict.get("won").reshape(-1)
        if self.win_rule == "game":
            return won
        score_win = get_game_spec(self.game).study_score_win if self.game is not None else None
        if score_win is not None:  # the study's rule for this game (GENERATORS.md §2)
            return next_tensordict.get("score").reshape(-1) >= score_win
        terminated = next_tensordict.get("terminated").reshape(-1)
        return won | ~terminated  # anything but a loss: a win or a step-limit timeout

    def update(self, outcomes: list[bool]) -> float:
        """Move the difficulty once per outcome (True = win), in order; returns the new value."""
        with exclusive(self.lock_path):
            value = float(self.shared_difficulty[0])
            if self.mode == "progressive":
                for win in outcomes:
                    value = min(1.0, value + self.alpha) if win else max(0.0, value - self.alpha)
                    value = round(value, DECIMALS)
            self.shared_difficulty[0] = value
            self.episodes[0] += len(outcomes)
        return value

    def record(self, next_tensordict: TensorDictBase, finished: torch.Tensor) -> None:
        """The episodes ``finished`` (``[B]`` bool) ended at this step: move the difficulty once
        per episode, in env order. The step calls it (the training env), and so does the
        Gymnasium env, which steps its env unwrapped (``Curriculum.episodes_ended``)."""
        if bool(finished.any()):
            self.update(self.wins(next_tensordict)[finished].tolist())

    def _step(self, tensordict: TensorDictBase, next_tensordict: TensorDictBase) -> TensorDictBase:
        self.record(next_tensordict, next_tensordict.get("done").reshape(-1))
        return self._write(next_tensordict)

    def _write(self, tensordict: TensorDictBase) -> TensorDictBase:
        shape = (*tensordict.batch_size, 1)
        value = self.shared_difficulty.to(device=tensordict.device)
        tensordict.set("difficulty", value.expand(shape).clone())
        return tensordict

    def _reset_env_preprocess(self, tensordict: TensorDictBase | None) -> TensorDictBase:
        if tensordict is None:
            parent = self.parent
            tensordict = parent.base_env.full_done_spec.zero().empty() if parent is not None else None
            if tensordict is None:
                raise RuntimeError("DifficultyTransform must be attached to an env before reset")
        return self._write(tensordict)

    def _reset(self, tensordict: TensorDictBase, tensordict_reset: TensorDictBase) -> TensorDictBase:
        return self._write(tensordict_reset)

    def _call(self, next_tensordict: TensorDictBase) -> TensorDictBase:
        return self._write(next_tensordict)

    def __repr__(self) -> str:
        return (
            f"DifficultyTransform(mode={self.mode!r}, d={self.difficulty:.2f}, alpha={self.alpha}, "
            f"win_rule={self.win_rule!r})"
        )
