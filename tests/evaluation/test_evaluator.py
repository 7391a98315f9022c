"""The evaluator on a tiny checkpoint: counts, the JSON-lines schema, reuse, and the CLI contracts."""

import json

import pytest
import torch
from tensordict import TensorDict

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.checkpoints import find_runs, run_info
from gvgai_pcg.evaluation.evaluator import evaluate_random, evaluate_run, read_records, run_results_path
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.evaluation.protocol import TEST_SETS, Protocol
from gvgai_pcg.levels import human_level

TINY = Protocol(test_levels=2, test_episodes=2, human_episodes=3, max_steps=15)
RECORD_KEYS = {
    "agent", "game", "test_set", "level", "level_seed", "episodes", "scores", "lengths", "wins",
    "max_score", "protocol", "frames", "checkpoint", "mean_score", "win_rate",
}  # fmt: skip


def test_run_info_reads_the_run_directory(tiny_run):
    info = run_info(tiny_run)
    assert (info.game, info.label, info.frames, info.training_sets) == ("zelda", "Lv 0", 1000, ("lv0",))
    assert find_runs([tiny_run.parent]) == [tiny_run]


def test_run_info_takes_whichever_model_trained_longer(tiny_run):
    """A resumed session killed before its end leaves a newer last.pt beside an older model.pt."""
    final = torch.load(tiny_run / "model.pt", weights_only=False)
    checkpoint = tiny_run / "checkpoints" / "last.pt"
    checkpoint.parent.mkdir()
    torch.save({**final, "frames": 5000}, checkpoint)
    assert (run_info(tiny_run).checkpoint, run_info(tiny_run).frames) == (checkpoint, 5000)
    torch.save({**final, "frames": 1000}, checkpoint)  # the same run's end: model.pt
    assert run_info(tiny_run).checkpoint == tiny_run / "model.pt"


def test_protocol_counts_and_schema(tiny_run):
    records = evaluate_run(run_info(tiny_run), TINY, progress=False)
    assert [r.test_set for r in records] == ["pcg0.5"] * 2 + ["pcg1"] * 2 + list(TEST_SETS[2:])
    assert [r.episodes for r in records] == [2, 2, 2, 2, 3, 3, 3, 3, 3]
    assert [r.level for r in records[4:]] == [f"zelda_lvl{i}" for i in range(5)]
    assert records[0].level == "zelda_pcg0.5_00" and records[0].level_seed >= 2**40
    for r in records:
        assert len(r.scores) == len(r.lengths) == len(r.wins) == r.episodes
        assert all(1 <= length <= TINY.max_steps for length in r.lengths)
    lines = run_results_path(tiny_run, TINY).read_text().splitlines()
    assert len(lines) == len(records)
    first = json.loads(lines[4])
    assert set(first) == RECORD_KEYS
    assert first["max_score"] == 8 and first["frames"] == 1000 and first["protocol"]["human_episodes"] == 3


def test_results_are_reused_until_the_checkpoint_changes(tiny_run, monkeypatch):
    first = evaluate_run(run_info(tiny_run), TINY, progress=False)
    import gvgai_pcg.evaluation.evaluator as evaluator

    monkeypatch.setattr(evaluator, "evaluate_policy", lambda *a, **k: pytest.fail("evaluated again"))
    assert evaluate_run(run_info(tiny_run), TINY, progress=False) == first


def test_random_agent_results_are_cached_per_game_and_protocol(tmp_path):
    records = evaluate_random("zelda", TINY, cache_dir=tmp_path, progress=False)
    assert (tmp_path / "random" / f"zelda-{TINY.key}.jsonl").is_file()
    assert evaluate_random("zelda", TINY, cache_dir=tmp_path, progress=False) == records
    assert Protocol(human_episodes=3).key != TINY.key


def test_greedy_policy_takes_the_argmax(tiny_run):
    info = run_info(tiny_run)
    policy = load_policy(info, greedy=True)
    from gvgai_pcg.envs import GVGAIEnv

    td = GVGAIEnv("zelda", 3, human_level("zelda", 0)).reset()
    logits, _ = policy.net(td["tiles"])
    assert torch.equal(policy(td), logits.argmax(-1))
    sampled = load_policy(info, seed=1)(TensorDict({"tiles": td["tiles"]}, batch_size=[3]))
    assert sampled.shape == (3,) and int(sampled.max()) < logits.shape[-1]


def test_cli_evaluates_a_run_and_keeps_the_random_json_contract(tiny_run, tmp_path, capsys):
    args = ["--test-levels", "1", "--test-episodes", "1", "--human-episodes", "1", "--max-steps", "5"]
    assert main(["evaluate", str(tiny_run.parent), *args, "--no-progress"]) == 0
    protocol = Protocol(test_levels=1, test_episodes=1, human_episodes=1, max_steps=5)
    assert len(read_records(run_results_path(tiny_run, protocol))) == 7
    out = tmp_path / "random.json"
    legacy = ["--agent", "random", "--game", "zelda", "--levels", "human", "--episodes", "2"]
    assert main(["evaluate", *legacy, "--max-steps", "5", "--no-progress", "--json", str(out)]) == 0
    payload = json.loads(out.read_text())
    assert payload["game"] == "zelda" and len(payload["levels"]) == 5
    entry = payload["levels"][0]
    assert {
        "level",
        "episodes",
        "mean_score",
        "std_score",
        "win_rate",
        "mean_length",
        "scores",
        "lengths",
    } <= set(entry)
    assert entry["episodes"] == 2 and len(entry["scores"]) == 2


def test_the_evaluations_progress_line_names_its_run(tiny_run, monkeypatch):
    """Issue 37, finding 6: a report's progress lines said 'zelda: 300 episodes' for every run."""
    import gvgai_pcg.evaluation.runner as runner

    descriptions = []
    real = runner.progress_display
    monkeypatch.setattr(
        runner,
        "progress_display",
        lambda total, desc, *a, **k: descriptions.append(desc) or real(total, desc, *a, **k),
    )
    evaluate_run(run_info(tiny_run), Protocol(test_levels=1, test_episodes=1, human_episodes=1, max_steps=3))
    assert descriptions == [f"zelda {tiny_run.name}: 7 episodes"]
