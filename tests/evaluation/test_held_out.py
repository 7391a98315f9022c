"""Held-out scores over training: each snapshot of a run evaluated into a file of its own, the
scores per snapshot, the CLI's table and plot."""

import torch

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.evaluator import read_records, run_results_path
from gvgai_pcg.evaluation.held_out import (
    evaluate_snapshots,
    held_out_plot_path,
    held_out_scores,
    pick_snapshots,
    snapshot_results_path,
)
from gvgai_pcg.evaluation.protocol import Protocol
from gvgai_pcg.rundir.checkpoint import save_model
from gvgai_pcg.rundir.snapshots import snapshot_path

from .conftest import make_run, write_log

TINY = Protocol(test_sets="large", test_levels=2, human_episodes=1, max_steps=5)


def with_snapshots(tmp_path, frames=(500, 1000, 1500, 2000)):
    """A tiny run with a snapshot at each of ``frames`` (the run's untrained weights, perturbed)."""
    run = make_run(tmp_path / "runs", "lv0", seed=0, frames=frames[-1])
    final = torch.load(run / "model.pt", weights_only=False)
    for i, f in enumerate(frames):
        weights = {k: v + 0.01 * i for k, v in final["model"].items()}
        save_model(snapshot_path(run, f), weights, final["config"], f)
    write_log(run, [(f, 0.1 * i, 0.0) for i, f in enumerate(frames)])
    return run


def test_every_picks_the_first_snapshot_past_each_multiple(tmp_path):
    paths = [tmp_path / f"model-{f:010d}.pt" for f in (1000, 2000, 3000, 4100, 5000)]
    assert pick_snapshots(paths) == paths
    assert [p.name for p in pick_snapshots(paths, every=2000)] == [paths[1].name, paths[3].name]


def test_each_snapshot_is_evaluated_into_its_own_file_and_scored(tmp_path):
    run = with_snapshots(tmp_path, frames=(500, 1000))
    results = evaluate_snapshots(run, TINY, progress=False)
    assert sorted(results) == [500, 1000]
    for frames, records in results.items():
        kept = read_records(snapshot_results_path(run, TINY, frames))
        assert [r.frames for r in kept] == [frames] * len(kept)
        assert [r.scores for r in kept] == [r.scores for r in records]
        assert kept[0].level == "zelda_pcg0.5_large_000"
    assert not run_results_path(run, TINY).exists()  # the run's own results file is untouched
    curves = held_out_scores(results)
    assert set(curves) == {"pcg0.5", "pcg1", "lv0", "lv1", "lv2", "lv3", "lv4", "human"}
    human = [sum(curves[f"lv{i}"][0][1] for i in range(5)) / 5]
    assert [f for f, _ in curves["human"]] == [500, 1000] and curves["human"][0][1] == human[0]


def test_evaluate_snapshots_prints_a_table_and_draws_the_plot(tmp_path, capsys):
    run = with_snapshots(tmp_path)
    flags = ["--test-levels", "1", "--human-episodes", "0", "--max-steps", "5", "--every", "1000"]
    assert main(["evaluate", str(run), "--snapshots", *flags, "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert (
        "held-out mean score per snapshot" in out and "1,000" in out and "2,000" in out and "500 " not in out
    )
    large = Protocol(test_sets="large", test_levels=1, human_episodes=0, max_steps=5)
    assert held_out_plot_path(run, large).stat().st_size > 1000


def test_a_run_without_snapshots_is_refused_in_one_line(tmp_path):
    import pytest

    run = make_run(tmp_path / "runs", "lv0", seed=0)
    with pytest.raises(FileNotFoundError, match="keep_every_frames"):
        evaluate_snapshots(run, TINY, progress=False)
