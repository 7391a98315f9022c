"""The divergence guard: a non-finite loss, gradient norm or parameter stops the run before the
bad state is saved.

A diverged update (too high a learning rate, an exploding value) leaves NaN or inf in the
network; saved, it makes every resume crash and every evaluation meaningless. The guard looks at
the loss and the gradient norm of every update before the optimizer applies it, with one host
read of a two-element tensor (no other synchronisation), and at every parameter before a
checkpoint or the final model is written. A crash of the acting pass on non-finite action
probabilities (from finite but huge weights) is reported as the divergence it is.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TypeVar

import torch

from gvgai_pcg.rundir.checkpoint import nonfinite_names

# What torch.distributions.Categorical says when the policy's probabilities are not finite.
NONFINITE_SAMPLING = "probability tensor contains either"
T = TypeVar("T")


class DivergenceError(Exception):
    """Training produced a non-finite quantity; nothing from that update on was saved."""

    def __init__(self, frames: int, quantity: str, checkpoint: Path | None, checkpoint_frames: int) -> None:
        self.frames, self.quantity = frames, quantity
        self.checkpoint, self.checkpoint_frames = checkpoint, checkpoint_frames
        if checkpoint is not None and checkpoint.exists():
            good = f"the last good checkpoint is {checkpoint} ({checkpoint_frames} frames)"
        else:
            good = "no checkpoint was written before it"
        super().__init__(
            f"training diverged at {frames} frames: {quantity}; nothing was saved after it, {good}. "
            "A lower algo.lr (or algo.max_grad_norm) in a new run (another run_name) avoids it"
        )


class DivergenceGuard:
    """Checks each update and each state about to be saved; raises ``DivergenceError``.

    Args:
        checkpoint: the run's checkpoint file (named as the last good state in the error).
        checkpoint_frames: the frames of the checkpoint the run resumed from (0 for a new run).
    """

    def __init__(self, checkpoint: Path, checkpoint_frames: int = 0) -> None:
        self.checkpoint, self.checkpoint_frames = checkpoint, checkpoint_frames
        self.frames = checkpoint_frames  # as of the last update checked

    def saved(self, frames: int) -> None:
        """A good checkpoint of ``frames`` was written."""
        self.checkpoint_frames = frames

    def check_update(self, loss: torch.Tensor, grad_norm: torch.Tensor, frames: int) -> None:
        """Before ``optimizer.step()`` of the update that reaches ``frames``: both scalars finite
        (one host read)."""
        self.frames = frames
        pair = torch.stack([loss.detach().float(), grad_norm.detach().float()])
        if bool(pair.isfinite().all()):
            return
        loss_value, norm_value = pair.tolist()
        if not math.isfinite(loss_value):
            self.fail(frames, f"the loss is {loss_value}")
        self.fail(frames, f"the gradient norm is {norm_value}")

    def check_parameters(self, module: torch.nn.Module, frames: int) -> None:
        """Before a state is saved: every parameter finite."""
        bad = nonfinite_names(dict(module.named_parameters()))
        if bad:
            more = f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""
            self.fail(frames, f"parameter {bad[0]} is not finite{more}")

    def watch(self, batches: Iterable[T], module: torch.nn.Module) -> Iterator[T]:
        """``batches`` (the collector), with a crash of its acting pass explained (``explain``)."""
        iterator = iter(batches)
        while True:
            try:
                batch = next(iterator)
            except StopIteration:
                return
            except Exception as error:
                self.explain(error, module, self.frames)
                raise
            yield batch

    def explain(self, error: BaseException, module: torch.nn.Module, frames: int) -> None:
        """A crash while collecting: raise it as a divergence when that is what it is."""
        if NONFINITE_SAMPLING in str(error):
            self.fail(frames, "the policy's action probabilities are not finite (weights too large)")
        if nonfinite_names(dict(module.named_parameters())):
            self.check_parameters(module, frames)

    def fail(self, frames: int, quantity: str) -> None:
        raise DivergenceError(frames, quantity, self.checkpoint, self.checkpoint_frames)
