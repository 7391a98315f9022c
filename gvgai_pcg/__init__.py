"""gvgai_pcg: batched GVGAI games with procedural level generators, on TorchRL.

Importing the package registers the four games; the envs, generators and training code are
imported on first use so that ``import gvgai_pcg`` stays cheap.
"""

from gvgai_pcg.levels import Level, LevelFormatError, human_level, human_levels

__version__ = "0.1.0"
__all__ = ["Level", "LevelFormatError", "human_level", "human_levels", "__version__"]
