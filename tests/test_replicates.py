"""Conclusions across replicate routes (seasonloop.reporting.replicates) on cases with a known answer."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.reporting.comparisons import claim_cells, csv_reader, run_comparisons
from seasonloop.reporting.replicates import (
    claim_tally,
    claims_across_routes,
    claims_in,
    first_to_last,
    fraction_spread,
    pooled_comparisons,
)

SETTINGS = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)
VARIANTS = [("cosine", "single", "")]
LEARNERS = ["good", "bad", "same"]
CLAIMS = {
    "good_over_bad": {"says": "good against bad", "table": "learners", "first": "good", "second": "bad"},
    "every_learner": {"says": "every two learners", "table": "learners"},
}


def write_route(folder, good: np.ndarray, bad: np.ndarray) -> None:
    """One route's outcomes on pair summer-fall: `same` is a copy of `good`."""
    for name, correct in (("good", good), ("bad", bad), ("same", good)):
        (folder / name).mkdir(parents=True)
        n = len(correct)
        QueryOutcomes(np.arange(n), correct, np.zeros(n), np.ones(n, bool), correct, np.arange(n), np.zeros(n)).to_csv(
            folder / name / "summer-fall.csv"
        )


def routes(tmp_path, n_routes: int, n_queries: int, edge: int):
    """Routes on which `good` is right on `edge` more queries than `bad` (in one stretch), the rest alike."""
    folders = {}
    rng = np.random.default_rng(1)
    for route in range(n_routes):
        bad = rng.random(n_queries) < 0.5
        good = bad.copy()
        start = rng.integers(0, n_queries - edge)
        good[start : start + edge] = True
        bad[start : start + edge] = False
        write_route(tmp_path / f"route{route}", good, bad)
        folders[route] = tmp_path / f"route{route}"
    return folders


def readers(folders):
    """Each route's reader of its outcomes folder, keyed as `folders`."""
    return {key: csv_reader(folder) for key, folder in folders.items()}


def test_fraction_spread_over_routes():
    summaries = {
        "a": {"fraction_correct": {"pca": {"summer-fall": 0.5, "winter-fall": 0.25}}},
        "b": {"fraction_correct": {"pca": {"summer-fall": 0.7, "winter-fall": 0.25}}},
    }
    spread = fraction_spread(summaries)
    assert spread["pca"]["summer-fall"] == pytest.approx({"mean": 0.6, "std": 0.1414213, "min": 0.5, "max": 0.7})
    assert spread["pca"]["winter-fall"]["std"] == 0.0
    assert fraction_spread({"a": summaries["a"]})["pca"]["summer-fall"]["std"] == 0.0


def test_first_to_last_counts_routes_where_the_largest_training_set_is_above_the_smallest():
    def route(pca: list[float], ica: list[float]) -> dict:
        sets = ["summer+winter+spring+fall", "summer", "summer+winter"]  # not in size order
        return {"fraction_correct": {"pca": dict(zip(sets, pca)), "ica": dict(zip(sets, ica))}}

    records = {"a": route([0.9, 0.8, 0.1], [0.5, 0.5, 0.9]), "b": route([0.7, 0.8, 0.9], [0.6, 0.5, 0.1])}
    assert first_to_last(records) == {"pca": {"up": 1, "down": 1, "same": 0}, "ica": {"up": 1, "down": 0, "same": 1}}


def test_pooling_routes_finds_what_each_route_is_too_short_to_show(tmp_path):
    # a 12-query edge on each 60-query route: on a single route it is one stretch
    folders = routes(tmp_path, n_routes=10, n_queries=60, edge=12)
    single = [run_comparisons(folder, LEARNERS, VARIANTS, ["summer-fall"], SETTINGS) for folder in folders.values()]
    pooled = pooled_comparisons(readers(folders), LEARNERS, VARIANTS, ["summer-fall"], SETTINGS)
    verdicts = [claim_cells(record, CLAIMS["good_over_bad"])["summer-fall"] for record in single]
    # one stretch per route: McNemar would call it (12 wins, p 5e-4); along the route a 12-query
    # stretch is a run too long for 60 queries, and the test says so instead of a verdict
    assert verdicts == ["+20.0 (too few queries)"] * 10
    assert claim_cells(pooled, CLAIMS["good_over_bad"]) == {"summer-fall": "+20.0 ▲"}
    # identical learners: no difference, pooled or not
    same = {"says": "same", "table": "learners", "first": "good", "second": "same"}
    assert claim_cells(pooled, same) == {"summer-fall": "+0.0 ·"}
    rows = pooled["pairs"]["summer-fall"]["learners"]
    good_bad = next(row for row in rows if {row["first"], row["second"]} == {"good", "bad"})
    assert good_bad["first_only"] + good_bad["second_only"] == 10 * 12


def test_pooled_verdicts_do_not_depend_on_the_order_routes_are_read_in(tmp_path):
    folders = routes(tmp_path, n_routes=4, n_queries=60, edge=6)
    pooled = pooled_comparisons(readers(folders), LEARNERS, VARIANTS, ["summer-fall"], SETTINGS)
    reversed_order = dict(reversed(list(folders.items())))
    assert pooled_comparisons(readers(reversed_order), LEARNERS, VARIANTS, ["summer-fall"], SETTINGS) == pooled
    # the keys only name the routes: nothing is drawn at random
    rekeyed = {key + 10: folder for key, folder in folders.items()}
    assert pooled_comparisons(readers(rekeyed), LEARNERS, VARIANTS, ["summer-fall"], SETTINGS) == pooled


def test_claim_tally_counts_routes_each_way(tmp_path):
    folders = routes(tmp_path, n_routes=3, n_queries=60, edge=12)
    records = {
        folder.name: run_comparisons(folder, LEARNERS, VARIANTS, ["summer-fall"], SETTINGS)
        for folder in folders.values()
    }
    tally = claim_tally(records, CLAIMS)
    counts = tally["good_over_bad"]["summer-fall"]
    assert counts["ahead"] == 3 and counts["behind"] == 0
    assert counts["better"] + 0 <= 3 and counts["worse"] == 0
    whole = tally["every_learner"]["summer-fall"]
    assert whole["least_better"] <= whole["most_better"] <= 3 and whole["most_worse"] <= 3
    pooled = pooled_comparisons(readers(folders), LEARNERS, VARIANTS, ["summer-fall"], SETTINGS)
    across = claims_across_routes(records, pooled, CLAIMS)
    assert (
        across["good_over_bad"]["summer-fall"]["pooled"] == claim_cells(pooled, CLAIMS["good_over_bad"])["summer-fall"]
    )
    assert across["good_over_bad"]["summer-fall"]["ahead"] == 3


def test_pooling_refuses_routes_with_other_pairs(tmp_path):
    folders = routes(tmp_path, n_routes=2, n_queries=30, edge=5)
    (folders[1] / "bad" / "summer-fall.csv").unlink()
    with pytest.raises(ValueError, match="route1/bad/summer-fall.csv"):
        pooled_comparisons(readers(folders), LEARNERS, VARIANTS, ["summer-fall"], SETTINGS)


def test_claims_on_learners_the_run_lacks_are_left_out(tmp_path):
    folders = routes(tmp_path, n_routes=1, n_queries=30, edge=5)
    record = run_comparisons(folders[0], LEARNERS, VARIANTS, ["summer-fall"], SETTINGS)
    other = {"says": "ica against pca", "table": "learners", "first": "ica", "second": "pca"}
    no_table = {"says": "sequences", "table": "matchers+seq"}
    kept, left_out = claims_in(record, {**CLAIMS, "ica_over_pca": other, "sequences_help": no_table})
    assert list(kept) == list(CLAIMS) and left_out == ["ica_over_pca", "sequences_help"]


def shown(baseline: str, seed: int, experiments: dict[str, int], state: str | None = None) -> dict:
    """One baseline of `dvc exp show --json`: its params' seed and experiments name -> seed, in
    executor `state` (None: finished)."""

    def data(seed: int) -> dict:
        return {"params": {"params.yaml": {"data": {"synthetic": {"seed": seed}}}}}

    return {
        "rev": baseline,
        "data": data(seed),
        "experiments": [
            {
                "executor": state and {"state": state},
                "revs": [{"rev": f"{baseline}-{name}", "name": name, "data": data(s)}],
            }
            for name, s in experiments.items()
        ]
        or None,
    }


def test_routes_are_read_from_commits_with_the_same_pipeline():
    from tools.replicate_routes import routes_of

    exps = [
        {"rev": "workspace", "data": {}, "experiments": None},
        shown("c3", 0, {"route-7": 7, "route-5": 5}),  # newest commit with routes
        shown("c3", 0, {"route-9": 9}, state="failed"),  # no outputs: left out
        shown("c2", 0, {}),
        shown("c1", 0, {"route-1": 1, "route-5": 5}),  # same pipeline: its route-1 joins, route-5 is c3's
        shown("c0", 0, {"route-2": 2}),  # another pipeline: left out
    ]
    routes = routes_of(exps, lambda newer, older: older != "c0")
    assert routes == {
        "route-0 (baseline)": {"rev": "c3", "seed": 0},
        "route-1": {"rev": "c1-route-1", "seed": 1},
        "route-5": {"rev": "c3-route-5", "seed": 5},
        "route-7": {"rev": "c3-route-7", "seed": 7},
    }
    assert routes_of(exps[:1], lambda newer, older: True) == {}


def test_routes_of_a_preset_are_its_experiments_only():
    from tools.replicate_routes import routes_of

    exps = [
        shown("c3", 0, {"route-every_place-0": 0, "route-every_place-2": 2, "route-5": 5, "route-other-1": 1}),
        shown("c2", 0, {"route-every_place-1": 1}),
    ]
    routes = routes_of(exps, lambda newer, older: True, "every_place")
    # no committed baseline: the commit's own run has the committed params, not the preset's
    assert routes == {
        "route-every_place-0": {"rev": "c3-route-every_place-0", "seed": 0},
        "route-every_place-1": {"rev": "c2-route-every_place-1", "seed": 1},
        "route-every_place-2": {"rev": "c3-route-every_place-2", "seed": 2},
    }
    # and a preset's routes are not the committed params' routes
    assert set(routes_of(exps, lambda newer, older: True)) == {"route-0 (baseline)", "route-5"}


def test_a_preset_route_is_queued_with_the_presets_settings(monkeypatch):
    import subprocess

    import tools.replicate_routes as replicate

    calls = []

    def dvc(*args: str) -> subprocess.CompletedProcess:
        calls.append(args)
        done = "a route-every_place-2 Success\n\nWorker status: 0 active, 0 idle\n"
        return subprocess.CompletedProcess(args, 0, done if args == ("queue", "status") else "", "")

    monkeypatch.setattr(replicate, "dvc", dvc)
    monkeypatch.setattr(replicate, "start_workers", lambda jobs: None)
    monkeypatch.setattr(replicate.time, "sleep", lambda seconds: None)
    monkeypatch.setattr(replicate.subprocess, "run", lambda *a, **k: subprocess.CompletedProcess(a, 0, "", ""))
    assert replicate.queue_routes([2], jobs=1, stages=["summary"], preset="every_place")[1] == [2]
    queued = calls[0]
    assert queued[:5] == ("exp", "run", "--queue", "-n", "route-every_place-2")
    assert "synthetic.seed=2" in queued and "split.folds=10" in queued and queued[-1] == "summary"


def test_preset_settings_are_the_presets_values_as_dvc_sets_them():
    from tools.replicate_routes import preset_settings

    assert preset_settings(None) == []
    settings = preset_settings("real_half")
    assert "split.folds=10" in settings and "data.seasons=[summer, winter]" in settings
    with pytest.raises(FileNotFoundError, match="no_such_preset"):
        preset_settings("no_such_preset")


def test_the_queue_wait_starts_workers_again_when_they_all_exit_with_routes_queued(monkeypatch):
    import subprocess

    import tools.replicate_routes as replicate

    status = "Task  Name  Created  Status\n{rows}\n\nWorker status: {workers}\n"
    queued = status.format(rows="a route-3 Queued", workers="0 active, 0 idle")
    # asked every ~12 s of the fake clock: twice within 30 s of the start (the workers may not show
    # yet: waits), then started again; then the route runs and ends
    statuses = iter(
        [
            queued,
            queued,
            queued,
            status.format(rows="a route-3 Running", workers="1 active, 0 idle"),
            status.format(rows="a route-3 Success", workers="0 active, 0 idle"),
        ]
    )
    clock = iter(range(0, 10_000, 4))  # each look at the time 4 s after the one before
    started = []

    def dvc(*args: str) -> subprocess.CompletedProcess:
        return subprocess.CompletedProcess(args, 0, next(statuses) if args == ("queue", "status") else "", "")

    monkeypatch.setattr(replicate, "dvc", dvc)
    monkeypatch.setattr(replicate, "start_workers", started.append)
    monkeypatch.setattr(replicate.time, "monotonic", lambda: next(clock))
    monkeypatch.setattr(replicate.time, "sleep", lambda seconds: None)
    monkeypatch.setattr(replicate.subprocess, "run", lambda *a, **k: subprocess.CompletedProcess(a, 0, "", ""))
    # route-4, removed from the queue by hand, did not run: its seed is not among those the time covers
    assert replicate.queue_routes([3, 4], jobs=2, stages=["summary"])[1] == [3]
    assert started == [2, 2]


def test_a_route_runs_the_stages_whose_outputs_the_record_reads():
    from tools.replicate_routes import route_stages
    from tools.repository import REPO

    learners = yaml.safe_load((REPO / "params.yaml").read_text())["learners"]
    # each route's paired tests come from its outcomes (collect computes them), not from its compare stage
    expected = {"summary", "training_seasons", *(f"evaluate@{learner}" for learner in learners)}
    assert set(route_stages()) == expected
