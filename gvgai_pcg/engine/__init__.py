"""Plumbing below the games and the envs: copying env rows between batched tensors (``rows``) and
reusing large output buffers (``buffers``). Knows nothing of any game."""
