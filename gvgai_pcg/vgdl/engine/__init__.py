"""The generic step: a ``Game`` that runs any VGDL description whose features have kernels here.

``VGDLGame.from_file(path)`` / ``VGDLGame.from_text(text)`` parse a description, compile its plan
(``gvgai_pcg.vgdl.plan``), refuse in one line what has no kernel (``checks``) and give a game
with its own class, ticked eagerly or through the engine's compiled path. Unlike the rest of
``gvgai_pcg.vgdl`` this needs torch.
"""

from gvgai_pcg.vgdl.engine.game import VGDLGame

__all__ = ["VGDLGame"]
