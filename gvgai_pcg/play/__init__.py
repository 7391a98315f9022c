"""Playing a level by hand in the terminal (``gvgai-pcg play``): a session and its curses front end."""

from gvgai_pcg.play.session import PlaySession

__all__ = ["PlaySession"]
