"""boulderdash: implemented in its own change (see issues)."""
