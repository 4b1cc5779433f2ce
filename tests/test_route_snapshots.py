"""Routes kept in the repository (tools.route_snapshots) read as the experiments they were, and pool
only with routes of the same pipeline."""

from __future__ import annotations

import json

import numpy as np
import pytest

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.reporting.comparisons import comparisons_of, csv_reader, run_comparisons
from tools.route_snapshots import difference, fingerprint, keep, kept_routes, npz_reader, upstream, write_outcomes

SETTINGS = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)
VARIANTS = [("cosine", "single", ""), ("cosine", "sequence", "+seq")]
LEARNERS = ["pca", "ica"]
PAIRS = ["summer-fall", "winter-summer"]


def write_outcomes_dir(folder, seed: int) -> None:
    """Random outcomes of every learner, evaluation and pair; a pair's queries shared by its evaluations."""
    rng = np.random.default_rng(seed)
    for pair in PAIRS:
        places = np.sort(rng.choice(500, size=80, replace=False))
        for learner in LEARNERS:
            for _, _, suffix in VARIANTS:
                correct = rng.random(80) < 0.6
                n = len(places)
                (folder / learner).mkdir(parents=True, exist_ok=True)
                QueryOutcomes(places, correct, rng.random(n), np.ones(n, bool), correct, places, rng.random(n)).to_csv(
                    folder / learner / f"{pair}{suffix}.csv"
                )


def test_a_kept_routes_outcomes_give_the_paired_tests_its_compare_stage_gave(tmp_path):
    write_outcomes_dir(tmp_path / "outcomes", seed=0)
    write_outcomes(tmp_path / "outcomes", tmp_path / "outcomes.npz", LEARNERS, ["", "+seq"], PAIRS)
    from_csv, from_npz = csv_reader(tmp_path / "outcomes"), npz_reader(tmp_path / "outcomes.npz")
    for learner in LEARNERS:
        for pair in PAIRS:
            for array_csv, array_npz in zip(from_csv(learner, pair, "+seq"), from_npz(learner, pair, "+seq")):
                assert np.array_equal(array_csv, array_npz)
    staged = run_comparisons(tmp_path / "outcomes", LEARNERS, VARIANTS, PAIRS, SETTINGS)
    assert comparisons_of(from_npz, LEARNERS, VARIANTS, PAIRS, SETTINGS) == staged
    # a pair whose evaluations are not of the same queries: refused, naming the file
    QueryOutcomes.read_csv(tmp_path / "outcomes/ica/summer-fall+seq.csv").take(np.arange(10)).to_csv(
        tmp_path / "outcomes/ica/summer-fall+seq.csv"
    )
    with pytest.raises(ValueError, match="ica/summer-fall\\+seq.csv: other queries than summer-fall's"):
        write_outcomes(tmp_path / "outcomes", tmp_path / "other.npz", LEARNERS, ["", "+seq"], PAIRS)


def lock(seed: int, code: str = "abc", n_keep: int = 100) -> dict:
    """A dvc.lock of four stages: acquire -> fit -> evaluate, and a report nothing reads."""

    def dep(path: str, md5: str) -> dict:
        return {"path": path, "hash": "md5", "md5": md5}

    return {
        "schema": "2.0",
        "stages": {
            "acquire": {
                "cmd": "python stages/acquire.py",
                "deps": [dep("src/seasonloop/data/synthetic", f"{code}.dir")],
                "params": {"params.yaml": {"synthetic": {"seed": seed, "seconds": 300}}},
                "outs": [{"path": "data/acquired", "md5": f"{seed}.dir"}],
            },
            "fit@pca": {
                "cmd": "python stages/fit.py pca",
                "deps": [dep("data/acquired", f"{seed}.dir"), dep("stages/fit.py", "f1")],
                "params": {"params.yaml": {"pca.n_keep": n_keep}},
                "outs": [{"path": "models/pca", "md5": f"m{seed}.dir"}],
            },
            "evaluate@pca": {
                "cmd": "python stages/evaluate.py pca",
                "deps": [dep("models/pca", f"m{seed}.dir"), dep("stages/evaluate.py", "e1")],
                "outs": [{"path": "data/outcomes/pca", "md5": f"o{seed}.dir"}],
            },
            "report": {
                "cmd": "python stages/report.py",
                "deps": [dep("data/outcomes", f"all{seed}.dir"), dep("stages/report.py", "r1")],
                "outs": [{"path": "plots/report.html", "md5": "h"}],
            },
        },
    }


def test_routes_of_one_pipeline_differ_only_in_their_seed():
    assert upstream(lock(0), ["evaluate@pca"]) == ["acquire", "evaluate@pca", "fit@pca"]
    first, second = fingerprint(lock(0), ["evaluate@pca"]), fingerprint(lock(7), ["evaluate@pca"])
    assert first == second and difference(first, second) is None
    # code or a param of a stage the routes run: not the same pipeline, named
    assert difference(first, fingerprint(lock(7, code="xyz"), ["evaluate@pca"])) == (
        "stage acquire: code src/seasonloop/data/synthetic"
    )
    assert difference(first, fingerprint(lock(7, n_keep=50), ["evaluate@pca"])) == "stage fit@pca: params"
    # data a stage reads from outside the pipeline (pretrained models, descriptors) is part of it too
    outside = lock(7)
    outside["stages"]["fit@pca"]["deps"].append({"path": "data/nordland/models", "hash": "md5", "md5": "x.dir"})
    other = lock(7)
    other["stages"]["fit@pca"]["deps"].append({"path": "data/nordland/models", "hash": "md5", "md5": "y.dir"})
    assert difference(fingerprint(outside, ["evaluate@pca"]), fingerprint(other, ["evaluate@pca"])) == (
        "stage fit@pca: code data/nordland/models"
    )
    # a stage a route's lock does not have (a preset with fewer learners) is left out, not a KeyError
    assert fingerprint(lock(0), ["evaluate@pca", "evaluate@hog"]) == first
    # a stage the routes do not run (the report) is not part of it
    changed = lock(7)
    changed["stages"]["report"]["deps"][1]["md5"] = "r2"
    assert difference(first, fingerprint(changed, ["evaluate@pca"])) is None


def test_a_kept_route_replaces_the_one_kept_before_and_is_found_by_its_preset(tmp_path, monkeypatch):
    import tools.route_snapshots as snapshots

    monkeypatch.setattr(snapshots, "KEPT", tmp_path / "kept")
    fetched = tmp_path / "fetched"
    write_outcomes_dir(fetched / "data" / "outcomes", seed=1)
    (fetched / "metrics").mkdir()
    for name in ("summary", "training_seasons"):
        (fetched / "metrics" / f"{name}.json").write_text(json.dumps({"fraction_correct": {}}))
    outcomes = {"learners": LEARNERS, "suffixes": ["", "+seq"], "pairs": PAIRS}
    route = {"seed": 3, "preset": "every_place", "rev": "e" * 40, "commit": "c" * 40, "fingerprint": {}}
    keep("route-every_place-3", fetched, route, outcomes)
    (snapshots.KEPT / "route-every_place-3" / "stale").write_text("")
    folder = keep("route-every_place-3", fetched, {**route, "rev": "f" * 40}, outcomes)
    assert sorted(path.name for path in folder.iterdir()) == [
        "outcomes.npz",
        "route.json",
        "summary.json",
        "training_seasons.json",
    ]
    found = kept_routes("every_place", snapshots.KEPT)
    assert list(found) == ["route-every_place-3"] and found["route-every_place-3"]["rev"] == "f" * 40
    assert kept_routes(None, snapshots.KEPT) == {}
    assert sorted(path.name for path in snapshots.KEPT.iterdir()) == ["route-every_place-3"]  # nothing staged left


def test_collect_pools_kept_routes_with_experiments_of_the_same_pipeline_only(monkeypatch, tmp_path):
    import tools.replicate_routes as replicate

    same = fingerprint(lock(0), ["evaluate@pca"])

    def route(seed: int, print_: dict, folder: bool) -> dict:
        params = {"synthetic": {"seed": seed, "seconds": 300}, "learners": ["pca"]}
        return {"seed": seed, "rev": f"{seed}" * 40, "commit": "c" * 40, "fingerprint": print_, "params": params} | (
            {"folder": tmp_path} if folder else {}
        )

    experiments = {"route-every_place-2": route(2, same, folder=False)}
    kept = {"route-every_place-0": route(0, same, True), "route-every_place-2": route(2, same, True)}
    monkeypatch.setattr(replicate, "found_routes", lambda preset: dict(experiments))
    monkeypatch.setattr(replicate, "kept_routes", lambda preset: dict(kept))
    routes = replicate.all_routes("every_place")
    # by seed; a seed both kept and among the experiments is read from the experiment
    assert list(routes) == ["route-every_place-0", "route-every_place-2"]
    assert "folder" not in routes["route-every_place-2"]
    kept["route-every_place-1"] = route(1, fingerprint(lock(1, n_keep=50), ["evaluate@pca"]), True)
    with pytest.raises(SystemExit, match="route-every_place-1 ran another pipeline than route-every_place-0 "):
        replicate.all_routes("every_place")
    kept["route-every_place-1"] = route(1, same, True) | {"params": {"synthetic": {"seed": 1}, "learners": ["ica"]}}
    with pytest.raises(SystemExit, match=r"route-every_place-1 ran another pipeline .*\(params.yaml\)"):
        replicate.all_routes("every_place")
    # one seed kept twice (two checkouts' experiments): refused, not pooled twice
    kept["route-every_place-1"] = route(1, same, True)
    kept["route-every_place-1 (other)"] = route(1, same, True)
    with pytest.raises(SystemExit, match="two routes of one seed"):
        replicate.all_routes("every_place")


def test_a_kept_route_names_the_queue_that_ran_it_and_the_line_counts_that_queue(tmp_path):
    import tools.replicate_routes as replicate

    saved = tmp_path / "queue.json"
    queue = {"seeds": [3, 2], "jobs": 1, "seconds": 7200.0, "preset": "every_place", "cpu": "AMD EPYC"}
    saved.write_text(json.dumps(queue))
    # other experiments in the repository (routes 0 and 1, from an earlier queue) do not matter
    assert replicate.queue_of(2, "every_place", saved)["seeds"] == [2, 3]
    assert replicate.queue_of(2, "every_place", saved)["queue_seconds"] == 7200.0
    assert replicate.queue_of(0, "every_place", saved)["queue_seconds"] is None  # another queue ran it
    assert replicate.queue_of(2, None, saved)["queue_seconds"] is None  # not under this preset
    assert replicate.queue_of(2, "every_place", tmp_path / "none.json")["seeds"] is None
    timed, untimed = replicate.queue_of(2, "every_place", saved), replicate.queue_of(0, "every_place", saved)
    assert timed["queue_cpu"] == "AMD EPYC" and untimed["queue_cpu"] is None
    record = {
        "preset": "every_place",
        "machine": {"cpu": "Intel Xeon"},  # the machine that collects, not the one that ran the queue
        "routes": {
            f"route-every_place-{seed}": {"seed": seed, "commit": "93e7ecc" + "0" * 33, "kept": True, "queue": queue}
            for seed, queue in ((0, untimed), (1, untimed), (2, timed))
        },
    }
    line = replicate._routes_line(record)
    assert "seed 0, 1 run at 93e7ecc (kept in docs/results/routes/);" in line
    assert (
        "seed 2 run at 93e7ecc (kept in docs/results/routes/): the queue of 2 routes took 120 min, 1 at a time, on AMD EPYC"
        in line
    )


def test_a_queue_whose_stages_came_from_the_run_cache_is_not_timed(tmp_path):
    import tools.replicate_routes as replicate

    log = (
        "Stage 'acquire' is cached - skipping run, checking out outputs\n"
        "Running stage 'fit@cae':\n"
        "Stage 'fit@pca' is cached - skipping run, checking out outputs\n"
        "Stage 'split' didn't change, skipping\n"
    )
    assert replicate.restored_in(log) == ["acquire", "fit@pca"]
    assert replicate.restored_in("Running stage 'acquire':\n") == []
    saved = tmp_path / "queue.json"
    saved.write_text(json.dumps({"seeds": [4], "jobs": 1, "seconds": None, "preset": "every_place", "cpu": "AMD"}))
    queue = replicate.queue_of(4, "every_place", saved)
    assert queue["seeds"] == [4] and queue["queue_seconds"] is None and queue["queue_cpu"] is None
