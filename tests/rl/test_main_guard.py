"""Training with collector workers from a script without a main guard: one line, a non-zero exit
and nothing written, never a traceback followed by a hang."""

from __future__ import annotations

import subprocess
import sys
import types
from pathlib import Path

import pytest

from gvgai_pcg.rl.main_guard import MissingMainGuardError, refuse_without_main_guard

CALL = "from gvgai_pcg.rl.main_guard import refuse_without_main_guard\n"


def _run_as_main(monkeypatch, path: Path, source: str, name: str = "__main__") -> None:
    """Run ``source`` as the top level of the main script ``path`` (as ``python path`` would; with
    ``name="__mp_main__"`` as a spawned worker runs it again)."""
    path.write_text(source)
    main = types.ModuleType(name)
    main.__file__ = str(path)
    monkeypatch.setitem(sys.modules, "__main__", main)
    exec(compile(source, str(path), "exec"), vars(main))


def test_a_call_from_the_top_level_of_a_script_is_refused_naming_its_line(tmp_path, monkeypatch):
    script = tmp_path / "train_it.py"
    with pytest.raises(MissingMainGuardError) as refused:
        _run_as_main(monkeypatch, script, CALL + "x = 1\nrefuse_without_main_guard()\n")
    line = str(refused.value.code)
    assert f"{script}:3 outside a main guard" in line and 'if __name__ == "__main__":' in line
    assert "\n" not in line


def test_a_call_from_a_function_called_at_the_top_level_is_refused_too(tmp_path, monkeypatch):
    source = CALL + "def run():\n    refuse_without_main_guard()\n\nif True:\n    run()\n"
    with pytest.raises(MissingMainGuardError, match=":6 outside a main guard"):
        _run_as_main(monkeypatch, tmp_path / "script.py", source)


@pytest.mark.parametrize("test", ['__name__ == "__main__"', "'__main__' == __name__"])
def test_a_call_under_a_main_guard_is_accepted(test, tmp_path, monkeypatch):
    source = CALL + f"def run():\n    refuse_without_main_guard()\n\nif {test}:\n    run()\n"
    _run_as_main(monkeypatch, tmp_path / "script.py", source)


def test_the_else_of_a_main_guard_is_not_guarded(tmp_path, monkeypatch):
    source = CALL + 'if __name__ == "__main__":\n    pass\nelse:\n    refuse_without_main_guard()\n'
    with pytest.raises(MissingMainGuardError, match=":5 outside"):
        _run_as_main(monkeypatch, tmp_path / "script.py", source, name="__mp_main__")


def test_a_main_without_a_file_is_accepted(monkeypatch):
    monkeypatch.setitem(sys.modules, "__main__", types.ModuleType("__main__"))  # python -c, a notebook
    refuse_without_main_guard()


SCRIPT = """
from pathlib import Path
from gvgai_pcg.config import compose_config
from gvgai_pcg.rl import train
{patch}
cfg = compose_config([
    "game=zelda", "regimen=lv", "env.num_envs=2", "env.max_steps=10", "total_frames=40",
    "log.every_episodes=8", "log.curve=false", "out_dir=runs", "collector.workers=2",
])
train(cfg, Path(cfg.out_dir) / cfg.run_name)
print("trained")
"""


def _run_script(tmp_path: Path, patch: str = "") -> subprocess.CompletedProcess:
    script = tmp_path / "script.py"
    script.write_text(SCRIPT.format(patch=patch))
    return subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=240, cwd=tmp_path
    )


@pytest.mark.slow  # a second interpreter importing torch and hydra: ~15 s
def test_a_script_without_a_main_guard_is_one_line_and_writes_nothing(tmp_path):
    done = _run_script(tmp_path)
    assert done.returncode != 0 and "trained" not in done.stdout
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and 'if __name__ == "__main__":' in lines[0], done.stderr[-3000:]
    assert f"{tmp_path / 'script.py'}:10 outside a main guard" in lines[0]
    assert not (tmp_path / "runs").exists()


@pytest.mark.slow  # two worker processes that each import torch: ~30 s
def test_a_worker_that_runs_an_unguarded_script_again_stops_with_one_line_and_no_hang(tmp_path):
    # the parent cannot tell (as where it cannot read its own script): each worker refuses, and
    # the parent ends with the collector's error instead of waiting on them at exit
    done = _run_script(tmp_path, "import gvgai_pcg.rl.main_guard as g; g._unguarded_call_line = lambda: None")
    assert done.returncode != 0 and "trained" not in done.stdout
    refusals = [line for line in done.stderr.splitlines() if "started again by a worker process" in line]
    assert refusals and 'if __name__ == "__main__":' in refusals[0], done.stderr[-3000:]
    assert "FolderInUseError" not in done.stderr
    assert done.stderr.strip().splitlines()[-1].startswith("RuntimeError: a collector worker failed to start")
