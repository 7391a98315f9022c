"""Models kept along a run (``checkpoint.keep_every_frames``): one per period, loadable as a
policy, and the same set after a stop and a resume as in one go."""

from __future__ import annotations

from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.rl import train
from gvgai_pcg.rundir.snapshots import snapshot_paths

# 8 envs x 5 steps = 40 frames a batch
TINY = ["regimen=lv", "env.num_envs=8", "env.max_steps=10", "log.every_episodes=8", "log.curve=false"]


def test_a_run_keeps_a_model_at_every_period_and_a_resume_keeps_the_same_ones(make_config, tmp_path):
    keep = ["checkpoint.keep_every_frames=80", "checkpoint.every_frames=40"]
    whole = make_config([*TINY, *keep, "total_frames=240", f"out_dir={tmp_path}", "run_name=whole"])
    train(whole, tmp_path / "whole")
    kept = [int(p.stem.split("-")[1]) for p in snapshot_paths(tmp_path / "whole")]
    assert kept == [80, 160, 240]
    policy = load_policy(snapshot_paths(tmp_path / "whole")[0])
    assert policy is not None

    first = make_config([*TINY, *keep, "total_frames=120", f"out_dir={tmp_path}", "run_name=cut"])
    train(first, tmp_path / "cut")
    second = make_config([*TINY, *keep, "total_frames=240", f"out_dir={tmp_path}", "run_name=cut"])
    train(second, tmp_path / "cut")
    assert [p.name for p in snapshot_paths(tmp_path / "cut")] == [
        p.name for p in snapshot_paths(tmp_path / "whole")
    ]


def test_no_model_is_kept_by_default(make_config, tmp_path):
    train(make_config([*TINY, "total_frames=120", f"out_dir={tmp_path}"]), tmp_path / "run")
    assert snapshot_paths(tmp_path / "run") == []
