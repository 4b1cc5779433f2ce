"""Blocked cross-validation along the route (split.folds): every place a test place once, by
learners that never saw it or its neighbours; the study's split is the last fold; one pair's result
pools every fold's queries; the folders each fold's files live in."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from sequence_settings import sequence_config

from seasonloop.data.datasets import count_folds, fold_dir, fold_dirs
from seasonloop.data.ground_truth import aligned_truth
from seasonloop.data.season_split import split_seasons
from seasonloop.data.split import fold_blocks, make_split
from seasonloop.evaluation.blocks import evaluate_in_blocks
from seasonloop.evaluation.folds import pooled_evaluation
from seasonloop.evaluation.metrics import evaluate_truth
from seasonloop.params.schema import check_params
from seasonloop.params.settings import EvaluateConfig, SplitConfig
from seasonloop.reporting.html import Text
from seasonloop.reporting.sections import dataset_section
from tools.small_runs import SMALL
from workspaces import committed_run, repro_with

REPO = Path(__file__).resolve().parents[1]

# (places, section_length, test_fraction, gap): the default route's, TINY's, sections of uneven
# length, a route shorter than one section
ROUTES = [(1800, 300, 0.1, 10), (300, 100, 0.3, 3), (1234, 300, 0.1, 10), (250, 300, 0.2, 4)]


def masks(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Random tunnels and stops: runs of a few places."""
    rng = np.random.default_rng(seed)
    tunnel, stop = np.zeros(n, bool), np.zeros(n, bool)
    for mask in (tunnel, stop):
        for start in rng.integers(0, n, 4):
            mask[start : start + rng.integers(1, 15)] = True
    return tunnel, stop


@pytest.mark.parametrize("n, length, fraction, gap", ROUTES)
def test_every_place_is_tested_once_by_learners_that_never_saw_it(n, length, fraction, gap):
    folds = round(1 / fraction)
    tunnel, stop = masks(n, seed=n)
    splits = [make_split(n, length, fraction, gap, tunnel, stop, folds=folds, fold=k) for k in range(folds)]
    tested = np.concatenate([split.test for split in splits])
    # every place but tunnels and stops, exactly once
    assert sorted(tested.tolist()) == np.flatnonzero(~tunnel & ~stop).tolist()
    for split, blocks in zip(splits, fold_blocks(n, length, fraction, folds)):
        near = np.zeros(n, bool)
        for start, end in blocks:
            near[max(0, start - gap) : end + gap] = True
        # no training place within gap of the fold's test blocks, and every other place trains
        assert not near[split.train].any()
        assert np.array_equal(np.sort(np.concatenate([split.train, np.flatnonzero(near)])), np.arange(n))
        # sequences never cross a block's end: a fold's test places are whole blocks
        assert set(split.test) <= set(np.flatnonzero(near))


@pytest.mark.parametrize("n, length, fraction, gap", ROUTES)
def test_the_study_split_is_the_last_fold(n, length, fraction, gap):
    tunnel, stop = masks(n, seed=1)
    study = make_split(n, length, fraction, gap, tunnel, stop)
    last = make_split(n, length, fraction, gap, tunnel, stop, folds=round(1 / fraction), fold=-1)
    assert last.to_json() == study.to_json()


def test_fold_blocks_tile_each_section_in_near_equal_blocks():
    blocks = fold_blocks(1800, 300, 0.1, 10)
    assert len(blocks) == 10 and all(len(fold) == 6 for fold in blocks)
    sizes = {end - start for fold in blocks for start, end in fold}
    assert sizes == {30}
    bounds = sorted(block for fold in blocks for block in fold)
    assert [end for _, end in bounds[:-1]] == [start for start, _ in bounds[1:]]  # contiguous, no overlap
    assert bounds[0][0] == 0 and bounds[-1][1] == 1800
    with pytest.raises(ValueError, match=r"split\.folds: a section of 5 places cannot hold 10 test blocks"):
        fold_blocks(5, 300, 0.1, 10)


def test_traverses_that_are_not_aligned_test_every_mapped_frame_once():
    n_reference, n_other = 400, 520  # the other season drives slower: more frames
    rng = np.random.default_rng(3)
    other = np.sort(rng.integers(-1, n_reference, n_other))  # -1: a frame on no reference place
    stats = {
        f"{season}_{kind}": np.full(n, value)
        for season, n in (("summer", n_reference), ("fall", n_other))
        for kind, value in (("brightness", 100.0), ("change", 5.0))
    }
    config = SplitConfig(
        section_length=100, test_fraction=0.25, gap=3, folds=4, dark_threshold=40, stop_threshold=1.0, test_every={}
    )
    mapped = {"summer": np.arange(n_reference), "fall": other}
    folds = [split_seasons(stats, ["summer", "fall"], config, mapped, fold) for fold in range(4)]
    for season, places in mapped.items():
        tested = np.concatenate([fold.season(season).test for fold in folds])
        assert sorted(tested.tolist()) == np.flatnonzero(places >= 0).tolist()
        for fold in folds:
            # a training frame of any season lies on a reference place outside the fold's blocks and gaps
            trained = places[fold.season(season).train]
            tested_places = places[fold.season(season).test]
            assert np.abs(trained[:, None] - tested_places[None, :]).min() > config.gap


@pytest.fixture
def params():
    return yaml.safe_load((REPO / "params.yaml").read_text())


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"folds": 0}, r"split\.folds: expected an integer >= 1, got 0"),
        ({"folds": 5}, r"split\.folds: 5; test blocks of split\.test_fraction 0\.1 tile a section in 10 folds"),
        ({"folds": 10, "test_fraction": 1}, r"split\.folds: 10, but split\.test_fraction 1 already tests every place"),
        # more folds than places per section
        ({"folds": 10, "section_length": 8}, r"leaves no training place"),
    ],
)
def test_a_bad_number_of_folds_is_one_line_naming_the_key(params, changes, message):
    bad = copy.deepcopy(params)
    bad["split"].update(changes)
    with pytest.raises(ValueError, match=message) as error:
        check_params(bad, ["split"])
    assert "\n" not in str(error.value)


def test_the_study_number_of_folds_passes(params):
    params["split"]["folds"] = 10
    check_params(params, ["split"])


def test_fold_folders(tmp_path):
    assert fold_dirs(tmp_path, 1) == [tmp_path]
    assert fold_dirs(tmp_path, 3) == [tmp_path / "folds/0", tmp_path / "folds/1", tmp_path]
    assert fold_dir(tmp_path, -1, 3) == tmp_path
    with pytest.raises(ValueError, match="fold 3 of 3"):
        fold_dir(tmp_path, 3, 3)
    assert count_folds(tmp_path) == 1
    for k in range(11):
        (tmp_path / "folds" / str(k)).mkdir(parents=True)
    assert count_folds(tmp_path) == 12
    (tmp_path / "folds/12").mkdir()
    with pytest.raises(ValueError, match="expected the folders 0 to 11"):
        count_folds(tmp_path)


EVALUATE = EvaluateConfig(
    pairs=("summer-fall",),
    metric="euclidean",
    extra_metrics=(),
    confidence="distance",
    ratio_exclusion=10,
    tolerance_frames=0,
    tolerance_m=10.0,
    matchers=("single",),
)


def fold_evaluation(rng, places, n_database=None):
    """A fold whose queries `places` are matched against its own database places (the same ones)."""
    database = places if n_database is None else places[:n_database]
    truth = aligned_truth(database, places, 0)
    distances = rng.random((len(places), len(database)))
    distances[np.arange(len(database)), np.arange(len(database))] -= rng.random(len(database)) * 0.8
    sequence = sequence_config(length=10, v_min=0.8, v_max=1.2, v_steps=5, window=10, window_at_breaks="ignore")
    return evaluate_in_blocks(lambda rows: distances[rows], len(database), truth, "single", EVALUATE, sequence), (
        distances,
        truth,
    )


def test_a_pair_pools_every_fold_s_queries_in_route_order():
    rng = np.random.default_rng(7)
    places = [np.r_[0:20, 60:80], np.r_[20:40, 80:100], np.r_[40:60, 100:120]]
    parts = [fold_evaluation(rng, fold) for fold in places]
    pooled = pooled_evaluation([evaluation for evaluation, _ in parts], "distance")
    assert pooled.outcomes.query_place.tolist() == list(range(120))
    correct = np.concatenate([evaluation.outcomes.correct for evaluation, _ in parts])
    assert pooled.metrics["fraction_correct"] == pytest.approx(correct.mean())
    assert pooled.metrics["n_queries"] == 120 and pooled.metrics["n_database"] == 40 and pooled.metrics["folds"] == 3
    # each query keeps its own fold's outcome
    for evaluation, _ in parts:
        rows = np.searchsorted(pooled.outcomes.query_place, evaluation.outcomes.query_place)
        assert np.array_equal(pooled.outcomes.match_place[rows], evaluation.outcomes.match_place)
        assert np.array_equal(pooled.outcomes.correct[rows], evaluation.outcomes.correct)
    # recall@N over all queries: the mean of the folds' weighted by their queries
    for n in (1, 5, 10):
        key = f"recall_at_{n}"
        assert pooled.metrics[key] == pytest.approx(np.mean([evaluation.metrics[key] for evaluation, _ in parts]))
    # the PR curve ranks every query's confidence together: the whole route's queries matched
    # against block-diagonal databases gives the same curve
    assert pooled.pr.iloc[-1]["precision"] == pytest.approx(correct.mean())


def test_one_fold_is_the_study_s_evaluation():
    rng = np.random.default_rng(8)
    evaluation, (distances, truth) = fold_evaluation(rng, np.arange(30))
    assert pooled_evaluation([evaluation], "distance") is evaluation
    metrics, _ = evaluate_truth(distances, truth, "distance", 10)
    assert metrics == evaluation.metrics


def test_a_fold_with_fewer_database_places_than_recall_at_10_counts_what_it_can():
    rng = np.random.default_rng(9)
    small, (_, truth) = fold_evaluation(rng, np.r_[0:6], n_database=6)
    large, _ = fold_evaluation(rng, np.r_[6:40])
    pooled = pooled_evaluation([small, large], "distance")
    hits = np.concatenate([small.outcomes.has_match, large.outcomes.has_match])
    assert hits.all()
    # the small fold's every query has its place among its 6: it counts as found at 10
    expected = (6 + large.metrics["recall_at_10"] * 34) / 40
    assert pooled.metrics["recall_at_10"] == pytest.approx(expected)


@pytest.mark.e2e
def test_a_run_of_every_fold_tests_every_place_and_keeps_the_study_split(tmp_path, small_seed_cache):
    """split.folds on the seed's SMALL run: every place but tunnels and stops tested once, a
    training-free learner's outcomes on the study split's queries those of the run of one fold,
    and the study split's own learner the one that run fitted."""
    root = committed_run(tmp_path / "repo", small_seed_cache)
    study_outcomes = {path.name: pd.read_csv(path) for path in (root / "data/outcomes/raw_patchnorm").glob("*.csv")}
    study_model = (root / "models/pca/pca.joblib").read_bytes()
    folds = round(1 / SMALL["split"]["test_fraction"])
    result = repro_with(root, f"split.folds={folds}", targets=("evaluate@raw_patchnorm", "fit@pca"))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]

    splits = [json.loads((folder / "split.json").read_text()) for folder in fold_dirs(root / "data/split", folds)]
    tested = np.concatenate([split["test"] for split in splits])
    left_out = {place for split in splits for place in split["dropped_tunnel"] + split["dropped_stop"]}
    assert sorted(tested.tolist()) == sorted(set(range(splits[0]["n_places"])) - left_out)
    assert len(left_out) < 0.2 * splits[0]["n_places"]  # a route, not a route of tunnels

    assert study_outcomes
    for name, study in study_outcomes.items():
        pooled = pd.read_csv(root / "data/outcomes/raw_patchnorm" / name)
        assert len(pooled) == len(tested)
        assert pooled["query_place"].is_monotonic_increasing  # route order
        same = pooled.set_index("query_place").loc[study["query_place"]].reset_index()
        pd.testing.assert_frame_equal(same, study, obj=name)

    assert (root / "models/pca/pca.joblib").read_bytes() == study_model
    fit = json.loads((root / "metrics/fit/pca.json").read_text())
    assert [entry["fold"] for entry in fit["folds"]] == list(range(folds - 1))
    assert all((root / f"models/pca/folds/{k}/pca.joblib").is_file() for k in range(folds - 1))

    # the folds fitted two at once (joblib), one thread each: the bytes of one after another
    def fold_models(jobs: int) -> list[bytes]:
        result = repro_with(root, f"split.folds={folds}", f"train.jobs={jobs}", "train.threads=1", targets=("fit@pca",))
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
        return [path.read_bytes() for path in sorted((root / "models/pca").rglob("pca.joblib"))]

    assert fold_models(2) == fold_models(1)


def test_the_report_says_which_numbers_pool_the_folds():
    dataset = {
        "seasons": {"summer": {"frames": 300, "train": 180, "test": 81, "train_augmented": 360}},
        "dropped_tunnel": 2,
        "dropped_stop": 5,
        "gap": 12,
        "folds": {"count": 3, "test": {"summer": 270}, "train": {"summer": [180, 177, 195]}},
    }
    text = [block.text for block in dataset_section(dataset, Path("preview.png")).blocks if isinstance(block, Text)]
    assert any("3 folds" in line and "summer 270" in line and "the study's split alone" in line for line in text)
    del dataset["folds"]
    assert not [block for block in dataset_section(dataset, Path("preview.png")).blocks if isinstance(block, Text)]
