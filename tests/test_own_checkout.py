"""Stages, tools and benchmarks run the library of their own checkout: the code dvc.yaml declares and
DVC hashes, and the commit a record names. An editable install points at one checkout's src/; a
second clone, or DVC's experiment queue running a copy of this tree, would otherwise run that one."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
STAGES = sorted(path.name for path in (REPO / "stages").glob("[!_]*.py"))
MARK = "the copy's own library"  # what the copy's library says when it is imported


@pytest.fixture(scope="module")
def copy(tmp_path_factory) -> Path:
    """The repository's code copied, its library changed so that importing it says so and stops."""
    root = tmp_path_factory.mktemp("checkout")
    skip = shutil.ignore_patterns("__pycache__", "*.egg-info", "results")
    for folder in ("src", "stages", "tools", "benchmarks"):
        shutil.copytree(REPO / folder, root / folder, ignore=skip)
    (root / "src" / "seasonloop" / "__init__.py").write_text(f"raise SystemExit({MARK!r})\n")
    return root


def run(root: Path, *args: str) -> subprocess.CompletedProcess:
    """python args in root, without PYTHONPATH: only the installed library and the checkout's own."""
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    return subprocess.run([sys.executable, *args], cwd=root, env=env, capture_output=True, text=True)


@pytest.mark.parametrize("stage", STAGES)
def test_every_stage_imports_its_own_checkouts_library(copy, stage):
    result = run(copy, f"stages/{stage}")
    assert result.returncode != 0 and MARK in result.stderr, result.stderr[-2000:]


@pytest.mark.parametrize("package", ["tools", "benchmarks"])
def test_tools_and_benchmarks_import_their_own_checkouts_library(copy, package):
    result = run(copy, "-c", f"import {package}, seasonloop")
    assert result.returncode != 0 and MARK in result.stderr, result.stderr[-2000:]


def test_without_them_python_finds_another_library(copy):
    """The tests above can fail: in the copy, a plain import finds the installed library, not the
    copy's."""
    result = run(copy, "-c", "import seasonloop; print(seasonloop.__file__)")
    assert result.returncode == 0 and not Path(result.stdout.strip()).is_relative_to(copy), result.stderr
