"""The study's pages: the results pages' generated blocks (tables, claims, the curricula comparison,
the runs awaiting retraining) and ``gvgai-pcg report --ued``'s table, written from the verdicts.
"""
