"""Staged writes: nothing half-written survives, not even what a killed run left behind."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from seasonloop.io import remove_stale_staging, staged_dir, staged_file, write_json

REPO = Path(__file__).resolve().parents[1]


def test_a_killed_runs_staging_is_removed_on_the_next_run(tmp_path):
    final = tmp_path / "acquired"
    # what a SIGKILL during acquire leaves: a hidden staging folder beside the output
    stale = tmp_path / ".acquired.staging-abc123"
    (stale / "summer.mp4").parent.mkdir(parents=True)
    (stale / "summer.mp4").write_bytes(b"partial")
    stale_file = tmp_path / ".sources.json.staging-xyz.json"
    stale_file.write_text("{")
    other = tmp_path / ".acquired_other.staging-1"  # another output's staging is left alone
    other.mkdir()
    with staged_dir(final) as out:
        (out / "sources.json").write_text("{}")
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        ".acquired_other.staging-1",
        ".sources.json.staging-xyz.json",
        "acquired",
    ]
    write_json(tmp_path / "sources.json", {})
    assert not stale_file.exists() and other.exists()
    assert remove_stale_staging(tmp_path / "acquired_other") == [other]


def test_a_failed_write_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError), staged_file(tmp_path / "a.json") as tmp:
        tmp.write_text("half")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_an_os_error_in_a_stage_is_one_line(tmp_path):
    # e.g. a full disk while acquire writes the rendered videos
    script = tmp_path / "stage.py"
    script.write_text(
        f"import sys\nsys.path.insert(0, {str(REPO / 'stages')!r})\nfrom _common import stage_main\n"
        "@stage_main\ndef main():\n    raise OSError(28, 'No space left on device', 'data/.acquired.staging-1/summer.mp4')\n"
        "main()\n"
    )
    result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True)
    assert result.returncode == 1
    assert result.stderr.strip().splitlines() == [
        "error: [Errno 28] No space left on device: 'data/.acquired.staging-1/summer.mp4'"
    ]
