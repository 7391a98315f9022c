"""Benchmark and device tools: what ``gvgai-pcg bench`` measures (env, engine and generator
throughput, peers, whole jobs, the speed targets), the scripts run by hand (``python -m
gvgai_pcg.bench.compiled``, ``.threads``, ``.training``, ``.device_check``) and the one timing
loop they share (``timing``). Only the commands import it: it sits beside the reports, above the
rest of the package."""
