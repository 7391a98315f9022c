"""Reinforcement learning: actor-critic networks, the learners (A2C, PPO; ``gvgai_pcg.rl.learners``),
the training loop shared by them and its session; the run directory's files (checkpoints, the log)
are ``gvgai_pcg.rundir``'s."""

from gvgai_pcg.rl.a2c_loss import A2CLoss, nstep_returns
from gvgai_pcg.rl.models import MODELS, ActorCritic, make_actor_critic
from gvgai_pcg.rl.training import TrainResult, train
from gvgai_pcg.rundir.checkpoint import CheckpointError

__all__ = [
    "MODELS",
    "A2CLoss",
    "ActorCritic",
    "CheckpointError",
    "TrainResult",
    "make_actor_critic",
    "nstep_returns",
    "train",
]
