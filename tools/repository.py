"""Copies of the repository for runs that start from nothing (the end-to-end tests' workspaces, the
benchmarks that time a fresh clone), and the environment their git and DVC commands run in."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

REPO = Path(__file__).resolve().parents[1]

# What `dvc repro` writes: a developer's checkout may hold them, a fresh clone does not.
PIPELINE_OUTPUTS = ("data/", "models/", "metrics/", "plots/", "logs/", "dvc.lock", "benchmarks/results/")


def merge(base: dict, override: dict) -> dict:
    for key, value in override.items():
        base[key] = merge(base[key], value) if isinstance(value, dict) and isinstance(base.get(key), dict) else value
    return base


def source_files() -> list[str]:
    """The repository as a fresh clone would have it, plus uncommitted source changes."""
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard"],
        cwd=REPO,
        check=True,
        capture_output=True,
        text=True,
    ).stdout.split()
    # data/nordland/ holds the tracked placeholders of the real-data folders
    return [
        name
        for name in listed
        if (REPO / name).is_file() and (not name.startswith(PIPELINE_OUTPUTS) or name.startswith("data/nordland/"))
    ]


def git(root: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        ["git", "-c", "user.name=t", "-c", "user.email=t@t", *args], cwd=root, capture_output=True, text=True
    )


def write_params(root: Path, overrides: dict) -> None:
    """root/params.yaml: the repository's params merged with `overrides`."""
    params = merge(yaml.safe_load((REPO / "params.yaml").read_text()), overrides)
    (root / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))


def copy_sources(root: Path) -> None:
    """The repository's source files at root, as a fresh clone has them (plus uncommitted changes)."""
    for name in source_files():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / name, root / name)


def commit_all(root: Path) -> None:
    """A new git repository at root holding everything there in one commit."""
    for command in (["init", "-q"], ["add", "-A"], ["commit", "-qm", "tiny"]):
        assert git(root, *command).returncode == 0


def tool_env(**extra: str) -> dict[str, str]:
    """This environment with the test's Python (and its dvc) first on PATH, writing bytecode as
    Python does by default (a sandbox's PYTHONDONTWRITEBYTECODE would make every stage process
    compile the package's modules again; .dvcignore keeps the bytecode out of DVC's hashes)."""
    env = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
    return dict(env, **extra, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")


def start_queue(root: Path, *args: str) -> subprocess.CompletedProcess:
    """`dvc queue start [args]` in root, with tool_env(), its output (stdout and stderr together)
    read from a file: the workers it starts keep the stdout and stderr they were given, and whoever
    reads a pipe waits until the last worker exits, ~10 s after the queue is empty."""
    with tempfile.TemporaryFile("w+") as said:
        started = subprocess.run(
            [str(Path(sys.executable).parent / "dvc"), "queue", "start", *args],
            cwd=root,
            env=tool_env(),
            stdout=said,
            stderr=subprocess.STDOUT,
        )
        said.seek(0)
        return subprocess.CompletedProcess(started.args, started.returncode, said.read(), "")


def dvc(root: Path, *args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    """A dvc command in root, with tool_env() (or `env`)."""
    return subprocess.run(
        [str(Path(sys.executable).parent / "dvc"), *args],
        cwd=root,
        env=env or tool_env(),
        capture_output=True,
        text=True,
    )


def learner_params(name: str, changes: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """params.yaml's section of learner `name` (its values: a learner declares only checks) with
    `changes` set: a learner as the project's params make it, for tests and benchmarks."""
    section = yaml.safe_load((REPO / "params.yaml").read_text())[name]
    return {**section, **(changes or {})}
