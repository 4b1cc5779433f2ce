"""docs/write_tables.py's run_state (tools.run_state): a table from a preset's run names a committed
state only when the run's folder is exactly that commit with the preset applied."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "docs"))

from write_tables import refuse_dirty, run_state  # noqa: E402

from seasonloop.preset import apply_preset  # noqa: E402
from tools.run_state import applied_preset  # noqa: E402


def git(folder: Path, *args: str) -> None:
    subprocess.run(["git", "-C", str(folder), *args], check=True, capture_output=True)


@pytest.fixture
def clone(tmp_path: Path) -> Path:
    (tmp_path / "presets").mkdir()
    (tmp_path / "presets" / "wide.yaml").write_text("split:\n  folds: 10\n")
    (tmp_path / "params.yaml").write_text("split:\n  folds: 1  # the study's split\n")
    (tmp_path / "dvc.lock").write_text("schema: '2.0'\n")
    (tmp_path / "metrics").mkdir()
    (tmp_path / "metrics" / ".gitignore").write_text("/summary.json\n")
    git(tmp_path, "init", "-q")
    git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "add", ".")
    git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "start")
    return tmp_path


def test_a_preset_run_is_its_commit_and_the_command_that_reproduces_it(clone):
    apply_preset("wide", clone / "params.yaml", clone / "presets")
    (clone / "dvc.lock").write_text("schema: '2.0'\nstages: {}\n")  # dvc repro rewrites the lock
    commit, dirty, command = run_state(clone, "dvc repro", "wide")
    assert not dirty and command == "python -m seasonloop.preset wide && dvc repro" and len(commit) >= 7
    assert run_state(clone, "dvc repro")[1]  # without the preset named: changes not committed


def test_dvc_entries_added_to_a_gitignore_are_the_run_s_bookkeeping_other_lines_are_not(clone):
    apply_preset("wide", clone / "params.yaml", clone / "presets")
    ignore = clone / "metrics" / ".gitignore"
    ignore.write_text("/summary.json\n/network_training.json\n")  # dvc repro: an output new to the commit
    assert run_state(clone, "dvc repro", "wide")[1] is False
    ignore.write_text("/summary.json\n*.json\n")
    with pytest.raises(ValueError, match="changed: metrics/.gitignore"):
        run_state(clone, "dvc repro", "wide")
    ignore.write_text("/network_training.json\n")  # an entry removed
    with pytest.raises(ValueError, match="changed: metrics/.gitignore"):
        run_state(clone, "dvc repro", "wide")


def test_params_edited_beyond_the_preset_are_refused(clone):
    apply_preset("wide", clone / "params.yaml", clone / "presets")
    with (clone / "params.yaml").open("a") as file:
        file.write("seed: 1\n")
    with pytest.raises(ValueError, match="params.yaml is not preset wide applied"):
        run_state(clone, "dvc repro", "wide")


def test_another_changed_file_is_refused(clone):
    apply_preset("wide", clone / "params.yaml", clone / "presets")
    (clone / "presets" / "wide.yaml").write_text("split:\n  folds: 5\n")
    with pytest.raises(ValueError, match="changed: presets/wide.yaml"):
        run_state(clone, "dvc repro", "wide")


def test_a_table_from_changes_not_committed_is_refused(clone):
    record = clone / "bench.json"
    record.write_text('{"commit": "abc1234", "dirty": true}')
    with pytest.raises(SystemExit, match="abc1234 \\+ changes not committed"):
        refuse_dirty(record, measured=True, dirty=False)
    record.write_text('{"commit": "abc1234", "dirty": false}')
    refuse_dirty(record, measured=True, dirty=True)  # a record says its own state
    with pytest.raises(SystemExit, match="changes not committed"):
        refuse_dirty(clone / "dvc.lock", measured=False, dirty=True)
    refuse_dirty(clone / "dvc.lock", measured=False, dirty=False)


def test_the_preset_a_run_applied_is_found_from_its_params_alone(clone):
    # the studies over finished runs (benchmarks/studies/) name each run's preset without being told
    assert applied_preset(clone) is None
    apply_preset("wide", clone / "params.yaml", clone / "presets")
    assert applied_preset(clone) == "wide"
    with (clone / "params.yaml").open("a") as file:
        file.write("seed: 1\n")
    with pytest.raises(ValueError, match="params.yaml: neither the commit's nor any preset"):
        applied_preset(clone)
