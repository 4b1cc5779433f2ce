"""End to end: the README's ablations as queued experiments run two at a time, compared in a
readable `dvc exp show` and in `dvc plots diff`. (`dvc exp run <target>` in a fresh clone:
test_fresh_clone.py; a queued experiment on real frames: test_real_frames.py.)"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
import yaml
from workspaces import SMALL, committed_run, dvc, in_a_terminal, tool_env, wait_for_the_queue


@pytest.mark.e2e
def test_two_queued_experiments_run_side_by_side_and_compare(tmp_path, small_seed_cache):
    root = committed_run(tmp_path / "repo", SMALL, cache=small_seed_cache)
    for name, discard in (("discard-1", 1), ("discard-5", 5)):
        queued = dvc(root, "exp", "run", "--queue", "-n", name, "-S", f"pca.n_discard={discard}")
        assert queued.returncode == 0, queued.stderr
    assert dvc(root, "queue", "start", "-j", "2").returncode == 0
    status = wait_for_the_queue(root, experiments=2)
    assert "Failed" not in status, status + dvc(root, "queue", "logs", "discard-1").stdout[-3000:]
    shown = json.loads(dvc(root, "exp", "show", "--json").stdout)
    experiments = {
        exp["name"]: exp["data"]
        for baseline_row in shown
        for exp in (baseline_row.get("experiments") or [])
        for exp in exp["revs"]
        if exp.get("name")
    }
    assert {"discard-1", "discard-5"} <= set(experiments), list(experiments)
    fractions = {
        name: experiments[name]["metrics"]["metrics/mean_fraction_correct.json"]["data"]["pca"]
        for name in ("discard-1", "discard-5")
    }
    assert all(0 <= value <= 1 for value in fractions.values())
    # readable: only what differs, in short columns that fit a terminal
    # the command of README and docs/sharing.md: what differs, without the outputs' hashes (columns with a path)
    table = in_a_terminal(root, 120, "exp", "show", "--only-changed", "--drop", ".*/|^models$", "--no-pager")
    assert "pca.n_discard" in table and "pca+seq" in table and "raw_patchnorm" not in table
    assert "…" not in table, table  # nothing cut to fit 120 columns
    diff = dvc(root, "plots", "diff", "discard-1", "discard-5", "--json")
    assert diff.returncode == 0 and "plots/summary/pr/summer-fall.csv" in json.loads(diff.stdout)["data"]


@pytest.mark.e2e
def test_replicate_routes_run_as_experiments_and_are_read_back(tmp_path, small_seed_cache):
    root = committed_run(tmp_path / "repo", SMALL, cache=small_seed_cache)
    done = subprocess.run(
        [sys.executable, "benchmarks/replicate_routes.py", "run", "--seeds", "7"],
        cwd=root,
        env=tool_env(),
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    record = json.loads((root / "benchmarks/results/replicate_routes.json").read_text())
    own_seed = yaml.safe_load((root / "params.yaml").read_text())["synthetic"]["seed"]
    assert sorted(route["seed"] for route in record["routes"].values()) == sorted([own_seed, 7])
    assert record["queue_seconds"] > 0 and record["pairs"] == ["summer-fall", "winter-summer", "winter-fall"]
    # two routes: the spread is real (another route, other numbers), every cell ordered
    cells = [cell for by_pair in record["fraction_correct"].values() for cell in by_pair.values()]
    assert all(cell["min"] <= cell["mean"] <= cell["max"] for cell in cells)
    assert any(cell["min"] < cell["max"] for cell in cells)
    # the claims on learners this run has (raw_patchnorm, pca), tallied over both routes and pooled
    assert "sequences_help" in record["claims"] and "ica_over_pca" in record["claims_left_out"]
    for by_pair in record["claims"].values():
        for counts in by_pair.values():
            assert counts["pooled"] and all(value <= 2 for key, value in counts.items() if key != "pooled")
    # the training-season ablation of both routes: each learner's sets, and both routes counted once
    training = record["training_seasons"]
    assert set(training["fraction_correct"]) == set(training["first_to_last"]) and training["first_to_last"]
    assert all(sum(change.values()) == 2 for change in training["first_to_last"].values())
