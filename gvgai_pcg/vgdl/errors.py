"""The one error a VGDL description is refused with: ``path:line: what is wrong``.

A ``ValueError``, so that the command line prints it as one line (``gvgai_pcg.cli``) and
a caller that already handles bad input handles it too.
"""

from __future__ import annotations


class VGDLError(ValueError):
    """A VGDL description that Java would misread, or a feature this package refuses.

    ``line`` is 1-based, as an editor shows it; 0 where the culprit is the whole file.
    """

    def __init__(self, path: str, line: int, message: str) -> None:
        self.path, self.line, self.reason = path, line, message
        super().__init__(f"{path}:{line}: {message}")
