"""Reinforcement learning: actor-critic networks, the A2C loss, the training loop, checkpoints."""

from gvgai_pcg.rl.a2c import TrainResult, train
from gvgai_pcg.rl.a2c_loss import A2CLoss, nstep_returns
from gvgai_pcg.rl.checkpoint import CheckpointError
from gvgai_pcg.rl.models import MODELS, ActorCritic, make_actor_critic

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
