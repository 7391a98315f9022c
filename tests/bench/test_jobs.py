"""Whole jobs in the bench: the protocol timed on a published model (with a tiny protocol here),
the training job's three environments, and their tables and targets from fake times."""

import subprocess
from pathlib import Path

import pytest

from gvgai_pcg.bench import jobs as bench_jobs
from gvgai_pcg.bench.jobs import ProtocolTime, TrainingTime
from gvgai_pcg.evaluation.protocol import Protocol


def test_the_protocol_is_timed_on_the_published_model():
    tiny = Protocol(test_levels=1, human_episodes=1, max_steps=20)
    timed = bench_jobs.time_protocol(protocol=tiny)
    assert (timed.run, timed.game, timed.episodes) == ("p-e64-lr2e-3-pcg1-s0", "zelda", 2 + 5)
    assert 0 < timed.env_steps <= 7 * 20 and timed.wall_s > 0 and timed.cpu_s > 0
    assert "protocol on one run" in "\n".join(bench_jobs.protocol_lines(timed))


def test_cold_and_warm_share_one_inductor_cache_and_eager_turns_compiling_off(monkeypatch, tmp_path):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")  # inherited from the shell: must not leak into cold
    cold, warm, eager = (bench_jobs.training_environment(m, tmp_path) for m in ("cold", "warm", "eager"))
    assert cold["TORCHINDUCTOR_CACHE_DIR"] == warm["TORCHINDUCTOR_CACHE_DIR"] == str(tmp_path)
    assert "GVGAI_PCG_COMPILE" not in cold and "GVGAI_PCG_COMPILE" not in warm
    assert eager["GVGAI_PCG_COMPILE"] == "0"
    with pytest.raises(ValueError, match="valid ones are: cold, warm, eager"):
        bench_jobs.training_environment("hot", tmp_path)


def test_the_training_runs_in_order_each_in_its_own_folder_and_a_timeout_is_recorded(monkeypatch):
    calls = []

    def run(command, env, capture_output, timeout):
        calls.append((command, env["TORCHINDUCTOR_CACHE_DIR"], env.get("GVGAI_PCG_COMPILE")))
        if len(calls) == 3:
            raise subprocess.TimeoutExpired(command, timeout)
        return subprocess.CompletedProcess(command, 0)

    monkeypatch.setattr(bench_jobs.subprocess, "run", run)
    times = bench_jobs.time_training(frames=640)
    assert [(t.mode, t.returncode) for t in times] == [
        ("cold", 0),
        ("warm", 0),
        ("eager", bench_jobs.TIMED_OUT),
    ]
    commands = [command for command, _, _ in calls]
    assert all(
        "total_frames=640" in c and "game=frogs" in c and c[1:4] == ["-m", "gvgai_pcg.cli", "train"]
        for c in commands
    )
    assert len({Path(c[-1].removeprefix("out_dir=")).name for c in commands}) == 3
    assert len({cache for _, cache, _ in calls}) == 1 and [c for _, _, c in calls] == [None, None, "0"]


def test_the_training_table_and_targets_set_warm_against_eager():
    times = [TrainingTime("cold", 45.0, 0), TrainingTime("warm", 16.0, 0), TrainingTime("eager", 12.8, 0)]
    lines = bench_jobs.training_lines(times)
    assert lines[-3:] == ["| cold | 45.0 | 3.52x |", "| warm | 16.0 | 1.25x |", "| eager | 12.8 | 1.00x |"]
    protocol = ProtocolTime("run", "zelda", 210, 116_011, 31.0, 10.5)
    timed, training = bench_jobs.job_checks(protocol, times)
    assert (timed.measured, timed.met) == (31.0, False)
    assert training.met is True and round(training.measured, 2) == 1.25
    failed = [TrainingTime("warm", 16.0, 0), TrainingTime("eager", 1.0, 1)]
    assert bench_jobs.training_lines(failed)[-1] == "| eager (failed, exit 1) | 1.0 | - |"
    timed, training = bench_jobs.job_checks(None, failed)
    assert timed.met is None and training.met is None


def test_without_the_published_model_the_section_says_so(monkeypatch, tmp_path):
    monkeypatch.setattr(bench_jobs, "EVALUATED_RUN", tmp_path / "gone")
    monkeypatch.setattr(bench_jobs, "time_training", lambda: [TrainingTime("eager", 1.0, 0)])
    section = bench_jobs.jobs_section()
    assert f"No model at {tmp_path / 'gone'}: not measured." in section.text
    assert [check.met for check in section.checks] == [None, None]
