"""The training loop's former home: training is learner-neutral now (``gvgai_pcg.rl.training``),
and A2C is one learner among others (``gvgai_pcg.rl.learners.a2c``). Kept so that
``from gvgai_pcg.rl.a2c import train`` goes on working."""

from gvgai_pcg.rl.training import TrainResult, seed_everything, train

__all__ = ["TrainResult", "seed_everything", "train"]
