"""The wheel is a complete install: the Hydra configs and the level data are in it, and an install
from it (no source tree on the path) trains and evaluates."""

from __future__ import annotations

import fnmatch
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib")  # Python 3.11+
ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


def test_every_package_is_listed():
    found = {
        ".".join(path.parent.relative_to(ROOT).parts) for path in (ROOT / "gvgai_pcg").rglob("__init__.py")
    }
    assert set(PYPROJECT["packages"]) == found | {"gvgai_pcg.conf"}
    assert PYPROJECT["package-dir"] == {"gvgai_pcg.conf": "conf"}


def test_every_config_file_is_package_data():
    patterns = PYPROJECT["package-data"]["gvgai_pcg.conf"]
    files = [
        path.relative_to(ROOT / "conf").as_posix() for path in (ROOT / "conf").rglob("*") if path.is_file()
    ]
    assert files and all(
        any(fnmatch.fnmatch(f, p) and f.count("/") == p.count("/") for p in patterns) for f in files
    )


def _source_copy(tmp_path: Path) -> Path:
    """The checkout without its build outputs, so building does not write into it."""
    skip = shutil.ignore_patterns(".git", ".venv", "build", "site", "runs", "*.egg-info", "__pycache__")
    return Path(shutil.copytree(ROOT, tmp_path / "src", ignore=skip))


@pytest.mark.slow
def test_an_installed_wheel_trains_and_evaluates(tmp_path):
    wheels = tmp_path / "wheels"
    build = [
        sys.executable,
        "-m",
        "pip",
        "wheel",
        "-q",
        "--no-deps",
        "--no-build-isolation",
        "-w",
        str(wheels),
    ]
    subprocess.run([*build, str(_source_copy(tmp_path))], check=True, timeout=600)
    (wheel,) = wheels.glob("gvgai_pcg-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    for name in (
        "gvgai_pcg/conf/config.yaml",
        "gvgai_pcg/conf/regimen/levels.yaml",
        "gvgai_pcg/conf/hydra/launcher/slurm.yaml",
        "gvgai_pcg/games/zelda/human_levels/zelda_lvl0.txt",
        "gvgai_pcg/games/NOTICE",
        "gvgai_pcg/games/frogs/test_sets/manifest.csv",
        "gvgai_pcg/games/boulderdash/test_sets/boulderdash_pcg1_29.txt",
        "gvgai_pcg/games/frogs/test_sets/manifest_large.csv",
        "gvgai_pcg/games/zelda/test_sets/zelda_pcg1_large.txt",
        "gvgai_pcg/vgdl/descriptions/zelda.txt",
    ):
        assert name in names

    # A fresh venv with the wheel; its dependencies (torch ...) come from this interpreter's
    # site-packages through a .pth line, which adds that folder but not its editable install.
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    site = Path(
        subprocess.run(
            [venv / "bin" / "python", "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout.strip()
    )
    (site / "dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    pip = [venv / "bin" / "python", "-m", "pip", "install", "-q", "--no-deps", "--no-index", str(wheel)]
    subprocess.run(pip, check=True, timeout=300)

    work = tmp_path / "work"  # not the checkout: nothing of the source tree is importable here
    work.mkdir()
    env = {key: value for key, value in os.environ.items() if key not in ("PYTHONPATH", "GVGAI_PCG_DEBUG")}

    def run(*argv: str) -> str:
        done = subprocess.run(argv, cwd=work, env=env, capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, done.stderr
        return done.stdout

    where = run(
        str(venv / "bin" / "python"), "-c", "import gvgai_pcg.config as c; print(c.__file__, c.config_dir())"
    )
    assert where.split() == [
        str(site / "gvgai_pcg" / "config.py"),
        str(site / "gvgai_pcg" / "conf"),
    ]
    cli = str(venv / "bin" / "gvgai-pcg")
    tiny = [
        "env.num_envs=4",
        "env.max_steps=20",
        "total_frames=80",
        "log.every_episodes=4",
        "log.curve=false",
    ]
    out = run(cli, "train", "game=frogs", "regimen=lv", *tiny, "out_dir=runs")
    assert (
        "run directory:" in out and (work / "runs" / "frogs-lv0-tiles-compact-seed0" / "model.pt").is_file()
    )
    protocol = ["--test-levels", "1", "--human-episodes", "1", "--max-steps", "10", "--no-progress"]
    out = run(cli, "evaluate", "runs/frogs-lv0-tiles-compact-seed0", *protocol)
    assert "pcg0.5" in out and "lv4" in out
    done = subprocess.run([cli, "train", "total_frames=0"], cwd=work, env=env, capture_output=True, text=True)
    assert (
        done.returncode == 2
        and done.stderr == "gvgai-pcg train: error: total_frames=0: expected an integer >= 1\n"
    )
