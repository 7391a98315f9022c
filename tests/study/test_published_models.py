"""A published run carries its trained policy: weights only, loaded without running code, and
evaluated again from the published folder alone it gives the published numbers."""

from __future__ import annotations

import json
import shutil

import torch

from gvgai_pcg.evaluation.checkpoints import published_run_info, run_info
from gvgai_pcg.evaluation.evaluator import evaluate_policy
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.evaluation.protocol import Protocol
from gvgai_pcg.study.pipeline import publish
from tests.evaluation.conftest import make_run

TINY = Protocol(test_levels=2, test_episodes=1, human_episodes=1, max_steps=30)


def test_a_published_model_loads_weights_only_and_reproduces_its_published_scores(tmp_path):
    from gvgai_pcg.evaluation.evaluator import evaluate_run

    run = make_run(tmp_path / "out" / "runs", "ppcg", seed=3)
    published_records = evaluate_run(run_info(run), TINY, progress=False)
    dest = publish(tmp_path / "out", tmp_path / "published", TINY, [run])
    shutil.rmtree(tmp_path / "out")  # another machine: only the published folder is there

    copy = dest / "runs" / run.name
    assert json.loads((copy / "published.json").read_text())["copied"] == "model.pt"
    torch.load(copy / "model.pt", weights_only=True)  # tensors and plain data only
    info = published_run_info(copy)
    assert info.model_file == copy / "model.pt"
    policy = load_policy(info, greedy=TINY.greedy, seed=TINY.seed)
    again = evaluate_policy(info.game, policy, TINY, str(copy), info.obs, "cpu", False)
    assert [(r.test_set, r.level, r.scores) for r in again] == [
        (r.test_set, r.level, r.scores) for r in published_records
    ]
