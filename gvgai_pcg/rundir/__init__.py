"""The run directory's I/O: atomic files, the folder lock, the log, checkpoints and snapshots, the
provenance of each session, the stop signal and the setting aside of earlier outputs.

Below every layer that reads or writes a run directory (``rl``'s training session, ``evaluation``,
``report``, ``study``), so that none of them needs the training code for its files.
"""
