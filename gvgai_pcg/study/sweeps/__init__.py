"""The study's sweeps: their conditions and budgets, the runs borrowed from another sweep, the curricula
runs' extra records, the pilot, and publishing a sweep's runs into ``results/``.
"""
