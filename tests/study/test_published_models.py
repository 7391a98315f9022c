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
from gvgai_pcg.study.sweeps.publish import publish
from tests.evaluation.conftest import make_run

TEXTS = (".json", ".jsonl", ".yaml", ".csv")
TINY = Protocol(test_levels=2, test_episodes=1, human_episodes=1, max_steps=30)


def test_a_published_model_loads_weights_only_and_reproduces_its_published_scores(tmp_path):
    from gvgai_pcg.evaluation.evaluator import evaluate_run

    run = make_run(tmp_path / "out" / "runs", "ppcg", seed=3)
    published_records = evaluate_run(run_info(run), TINY, progress=False)
    dest = publish(tmp_path / "out", tmp_path / "published", TINY, [run])
    shutil.rmtree(tmp_path / "out")  # another machine: only the published folder is there

    copy = dest / "runs" / run.name
    assert json.loads((copy / "published.json").read_text()) == {"model": "model.pt", "frames": 1000}
    assert str(tmp_path) not in "".join(p.read_text() for p in copy.rglob("*") if p.suffix in TEXTS)
    torch.load(copy / "model.pt", weights_only=True)  # tensors and plain data only
    info = published_run_info(copy)
    assert info.model_file == copy / "model.pt"
    policy = load_policy(info, greedy=TINY.greedy, seed=TINY.seed)
    again = evaluate_policy(info.game, policy, TINY, str(copy), info.obs, "cpu", False)
    assert [(r.test_set, r.level, r.scores) for r in again] == [
        (r.test_set, r.level, r.scores) for r in published_records
    ]
    assert evaluate_run(info, TINY, progress=False)[0].checkpoint == "model.pt"  # current: not replayed
    other = Protocol(test_levels=1, test_episodes=1, human_episodes=1, max_steps=10)
    made_here = evaluate_run(info, other, progress=False)  # evaluated in the published folder
    assert {(r.agent, r.checkpoint) for r in made_here} == {(run.name, "model.pt")}


def test_a_real_published_model_gives_its_published_scores_again():
    """medium's Zelda Lv 4 seed 0, from the repository: the first two levels of each 100-level set
    and the first two episodes of each human level score as published (an episode's score does
    not depend on what else shares the batch, so a smaller protocol replays those episodes).

    Another CPU's kernels move the action probabilities by about 1e-7, which changes an episode
    only where a sampled action lands that close to a boundary between two actions: one record of
    the nine may differ. Weights changed by 1e-4 of their size still replay all nine; by 1e-2, two
    differ (and any change to the rules or the observations, most)."""
    from pathlib import Path

    copy = Path(__file__).resolve().parents[2] / "results/medium/runs/zelda-lv4-tiles-compact-seed0"
    published = {}
    for record in map(json.loads, (copy / "eval" / "protocol-da4831a216.jsonl").read_text().splitlines()):
        published[record["test_set"], record["level"]] = record["scores"]
    info = published_run_info(copy)
    small = Protocol(test_levels=2, test_sets="large", human_episodes=2)
    policy = load_policy(info, greedy=small.greedy, seed=small.seed)
    again = evaluate_policy(info.game, policy, small, str(copy), info.obs, "cpu", False)
    assert len(again) == 2 + 2 + 5
    differ = [
        (record.level, record.scores, published[record.test_set, record.level][: len(record.scores)])
        for record in again
        if record.scores != published[record.test_set, record.level][: len(record.scores)]
    ]
    assert len(differ) <= 1, differ
    assert max(max(r.scores) for r in again if r.test_set == "lv4") >= 5  # the level it trained on


def test_a_boulderdash_model_of_the_studys_size_is_published_whatever_its_size(tmp_path):
    """The study's network on Boulderdash is 0.75M parameters, 3 MB: published like any other."""
    import yaml

    from gvgai_pcg.evaluation.policy import observation_shape
    from gvgai_pcg.games import get_game
    from gvgai_pcg.rl.models import make_actor_critic

    run = make_run(tmp_path / "out" / "runs", "ppcg", seed=0, game="boulderdash")
    config = yaml.safe_load((run / "config.yaml").read_text())
    config["model"]["hidden"] = 256
    (run / "config.yaml").write_text(yaml.safe_dump(config))
    shape, actions = observation_shape("boulderdash", "tiles"), get_game("boulderdash").num_actions
    net = make_actor_critic("compact", "tiles", shape, actions, 256)
    torch.save({"model": net.state_dict(), "config": config, "frames": 1000}, run / "model.pt")
    dest = publish(tmp_path / "out", tmp_path / "published", None, [run])
    copy = dest / "runs" / run.name
    assert (copy / "model.pt").stat().st_size > 2_000_000
    state = torch.load(copy / "model.pt", weights_only=True)
    assert all(torch.equal(state["model"][k], v) for k, v in net.state_dict().items())
    assert published_run_info(copy).model_file == copy / "model.pt"


def test_publishing_again_from_a_copy_without_the_model_keeps_the_published_model(tmp_path):
    run = make_run(tmp_path / "out" / "runs", "ppcg", seed=1)
    dest = publish(tmp_path / "out", tmp_path / "published", None, [run])
    source = tmp_path / "copy" / "runs" / run.name  # the published run, its model gone
    shutil.copytree(dest / "runs" / run.name, source)
    (source / "model.pt").unlink()
    publish(tmp_path / "copy", dest, None, [source])
    assert json.loads((dest / "runs" / run.name / "published.json").read_text())["model"] == "model.pt"
    assert published_run_info(dest / "runs" / run.name).model_file.is_file()
