"""GVGAI's VGDL, read as GVGAI's Java engine reads it: the front end of the VGDL compiler.

``parse_file`` / ``parse_vgdl`` give a ``GameDescription`` (types with Java's classes and
defaults, the update order, collision pairs and EOS lists in Java's processing order);
anything Java would misread or this package does not know is refused with ``VGDLError``
(``path:line: ...``). ``compile_plan`` turns a description the engine supports into the
``Plan`` a generic step runs (``plan``). Pure Python: nothing here needs torch.
"""

from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.model import CollisionPair, Effect, GameDescription, SpriteType, Termination
from gvgai_pcg.vgdl.parser import parse_file, parse_vgdl
from gvgai_pcg.vgdl.plan import Plan, compile_plan

__all__ = [
    "CollisionPair",
    "Effect",
    "GameDescription",
    "Plan",
    "SpriteType",
    "Termination",
    "VGDLError",
    "compile_plan",
    "parse_file",
    "parse_vgdl",
]
