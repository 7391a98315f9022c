"""frogs: implemented in its own change (see issues)."""
