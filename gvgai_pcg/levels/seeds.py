"""The two seed ranges that keep training and evaluation apart.

Generated training levels draw their seeds from ``[0, TRAINING_SEED_SPACE)``; the frozen
evaluation test sets use seeds at and above ``TEST_SEED_BASE``, so no training episode can ever
see a test level. The study-sized (30-level) sets draw from ``[TEST_SEED_BASE, TEST_SEED_BASE + 2^24)``
and the 100-level sets from ``LARGE_TEST_SEED_BASE`` = ``TEST_SEED_BASE + 2^24`` up, so the two never
share a seed.
"""

TRAINING_SEED_SPACE = 2**31
TEST_SEED_BASE = 2**40
LARGE_TEST_SEED_BASE = TEST_SEED_BASE + 2**24
