"""gvgai_pcg: batched GVGAI games with procedural level generators, on TorchRL.

Importing the package registers the Gymnasium ids (``gvgai_pcg/Zelda-v0`` ...; Gymnasium 1.x
loads no plugins itself); the engine, envs, generators and training code are imported on first
use, so ``import gvgai_pcg`` stays cheap.
"""

from gvgai_pcg.envs.gym_registration import register_envs
from gvgai_pcg.levels import Level, LevelFormatError, human_level, human_levels

register_envs()

__version__ = "0.1.0"
__all__ = ["Level", "LevelFormatError", "human_level", "human_levels", "__version__"]
