"""The study's verdicts: its Table 1, our runs read into tables, the claims' rules, intervals over
seeds, and one judging system for the claims and the curricula comparison.
"""
