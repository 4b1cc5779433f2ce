"""Tests for benchmarks/studies/window_ceiling.py: the most queries a sequence descriptor can get
right, counted from a run's test blocks."""

from __future__ import annotations

import pytest

from benchmarks.studies.window_ceiling import run_ceiling
from seasonloop.io import write_json


def test_shared_windows_bound_the_queries_that_can_be_right(tmp_path):
    # one block of 30 places and one of 5 (a tunnel cut it): with L = 10, seqNet's shifted window
    # gives the long block 30 - 10 + 1 distinct windows and the short one a single window
    params = "data:\n  ground_truth: aligned\nevaluate:\n  tolerance_frames: 0\nsequence:\n  length: 10\n"
    (tmp_path / "params.yaml").write_text(params)
    write_json(tmp_path / "data/split/split.json", {"test": [*range(100, 130), *range(200, 205)], "n_places": 300})
    run = run_ceiling(tmp_path)
    assert (run["queries"], run["blocks"], run["median_block"], run["folds"]) == (35, 2, 17.5, 1)
    assert run["rules"]["shift"]["distinct_windows"] == 21 + 1
    # clipped windows are the frame's own, except in the short block, where every window is the block
    assert run["rules"]["clip"]["distinct_windows"] == 30 + 1
    assert run["rules"]["shift"]["ceiling"] == 22 / 35
    # with a tolerance, queries that share a window can all be right: no ceiling
    (tmp_path / "params.yaml").write_text(params.replace("tolerance_frames: 0", "tolerance_frames: 2"))
    with pytest.raises(ValueError, match="params.yaml: a ceiling needs data.ground_truth aligned"):
        run_ceiling(tmp_path)
