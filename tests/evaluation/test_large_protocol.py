"""The protocol on the 100-level test sets: its own key and results file, so the study-sized
records (and the published results named by their key) are untouched."""

import pytest

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.evaluator import evaluate_run, read_records, run_results_path
from gvgai_pcg.evaluation.protocol import LARGE_PROTOCOL, Protocol, protocol_test_sets
from gvgai_pcg.study.sweeps.conditions import BUDGETS

PUBLISHED_KEY = "efee2915b5"  # results/small/runs/*/eval/protocol-efee2915b5.jsonl


def test_the_study_sized_key_is_unchanged_and_the_large_one_differs():
    assert Protocol().key == Protocol(**BUDGETS["small"].protocol).key == PUBLISHED_KEY
    assert "test_sets" not in Protocol().as_dict()
    assert LARGE_PROTOCOL.key != PUBLISHED_KEY and LARGE_PROTOCOL.as_dict()["test_sets"] == "large"


def test_the_large_protocol_plays_a_hundred_levels_per_difficulty():
    sets = {s.name: s for s in protocol_test_sets("solarfox", LARGE_PROTOCOL)}
    assert [len(sets[name].levels) for name in ("pcg0.5", "pcg1")] == [100, 100]
    assert sets["pcg1"].levels[99].name == "solarfox_pcg1_large_099"
    assert len(sets["lv0"].levels) == 1 and sets["lv0"].episodes == 30


@pytest.mark.parametrize(
    ("settings", "says"),
    [
        ({"test_sets": "huge"}, "test_sets must be one of study, large"),
        ({"test_sets": "large", "test_levels": 101}, r"test_levels must be in 1\.\.100"),
        ({"test_levels": 31}, r"test_levels must be in 1\.\.30"),
    ],
)
def test_bad_sizes_are_refused_in_one_line(settings, says):
    with pytest.raises(ValueError, match=says):
        Protocol(**settings)


def test_evaluate_test_sets_large_files_its_records_beside_the_study_sized_ones(tiny_run):
    small = Protocol(test_levels=2, human_episodes=0, max_steps=5)
    evaluate_run(run_info(tiny_run), small, progress=False)
    flags = ["--test-sets", "large", "--test-levels", "3", "--human-episodes", "0", "--max-steps", "5"]
    assert main(["evaluate", str(tiny_run), *flags, "--no-progress"]) == 0
    large = Protocol(test_sets="large", test_levels=3, human_episodes=0, max_steps=5)
    records = read_records(run_results_path(tiny_run, large))
    assert [r.level for r in records] == [
        f"zelda_pcg{d}_large_{i:03d}" for d in ("0.5", "1") for i in range(3)
    ]
    assert records[0].protocol["test_sets"] == "large"
    kept = read_records(run_results_path(tiny_run, small))
    assert [r.level for r in kept] == ["zelda_pcg0.5_00", "zelda_pcg0.5_01", "zelda_pcg1_00", "zelda_pcg1_01"]
