"""End to end: the README's ablations and replicate routes as queued experiments run two at a time, compared in a
readable `dvc exp show` and in `dvc plots diff`. (`dvc exp run <target>` in a fresh clone:
test_fresh_clone.py; a queued experiment on real frames: test_real_frames.py.)"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
import yaml

from tools.repository import dvc, tool_env
from workspaces import committed_run, in_a_terminal


@pytest.mark.e2e
def test_queued_experiments_run_side_by_side_compare_and_replicate_routes(tmp_path, small_seed_cache):
    # one queue for both uses (each queue run costs a minute): an ablation queued by hand, and a
    # replicate route that tools/replicate_routes.py queues beside it and runs two at a time
    root = committed_run(tmp_path / "repo", small_seed_cache)
    queued = dvc(root, "exp", "run", "--queue", "-n", "discard-5", "-S", "pca.n_discard=5")
    assert queued.returncode == 0, queued.stderr
    done = subprocess.run(
        [sys.executable, "-m", "tools.replicate_routes", "run", "--seeds", "7", "--jobs", "2"],
        cwd=root,
        env=tool_env(),
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr[-3000:] + dvc(root, "queue", "logs", "discard-5").stdout[-3000:]
    replicate_record_holds_both_routes(
        json.loads((root / "benchmarks/results/replicate_routes.json").read_text()), root
    )
    # the route ran what the record reads, not the stages after it (tools.replicate_routes.route_stages)
    logs = dvc(root, "queue", "logs", "route-7").stdout
    assert "Running stage 'training_seasons'" in logs and "Running stage 'figures'" not in logs, logs[-3000:]
    # the route's experiment read, the ablation's compared alone
    assert dvc(root, "exp", "remove", "route-7").returncode == 0
    shown = json.loads(dvc(root, "exp", "show", "--json").stdout)
    experiments = {
        exp["name"]: exp["data"]
        for baseline_row in shown
        for exp in (baseline_row.get("experiments") or [])
        for exp in exp["revs"]
        if exp.get("name")
    }
    assert set(experiments) == {"discard-5"}, list(experiments)
    fraction = experiments["discard-5"]["metrics"]["metrics/mean_fraction_correct.json"]["data"]["pca"]
    assert 0 <= fraction <= 1
    # readable: only what differs, in short columns that fit a terminal
    # the command of README and docs/sharing.md: what differs, without the outputs' hashes (columns with a path)
    table = in_a_terminal(root, 120, "exp", "show", "--only-changed", "--drop", ".*/|^models$", "--no-pager")
    assert "pca.n_discard" in table and "pca+seq" in table and "raw_patchnorm" not in table
    assert "…" not in table, table  # nothing cut to fit 120 columns
    diff = dvc(root, "plots", "diff", "discard-5", "--json")
    assert diff.returncode == 0 and "plots/summary/pr/summer-fall.csv" in json.loads(diff.stdout)["data"]


def replicate_record_holds_both_routes(record: dict, root) -> None:
    own_seed = yaml.safe_load((root / "params.yaml").read_text())["synthetic"]["seed"]
    assert sorted(route["seed"] for route in record["routes"].values()) == sorted([own_seed, 7])
    assert record["queue_seconds"] > 0 and record["jobs"] == 2
    assert record["pairs"] == ["summer-fall", "winter-summer", "winter-fall"]
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
