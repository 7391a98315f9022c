"""How long a test waits for a subprocess (a training run, a second interpreter) before calling it
stuck. A wait ends as soon as what it waits for happens, so a long limit costs nothing when things
work; it must outlast a busy 2-core machine, where a run that starts in 20 s alone takes minutes
to import torch and write its first checkpoint beside five other test sessions."""

PATIENCE_S = 600
