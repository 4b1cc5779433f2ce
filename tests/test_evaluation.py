"""Tests for seasonloop.evaluation.matchers (metric x matcher variants, the matcher registry) and the PR landmarks."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from sequence_settings import sequence_config

from seasonloop.data.ground_truth import aligned_truth
from seasonloop.evaluation.blocks import pair_distances
from seasonloop.evaluation.distances import distance_matrix
from seasonloop.evaluation.matchers import (
    MATCHER_REGISTRY,
    MATCHERS,
    evaluations,
    get_matcher,
    match_distances,
    result_suffix,
)
from seasonloop.evaluation.sequence import sequence_distances
from seasonloop.params.settings import EvaluateConfig
from seasonloop.reporting.summary import pr_landmarks, pr_landmarks_table

PARAMS = yaml.safe_load((Path(__file__).resolve().parents[1] / "params.yaml").read_text())
EVALUATE = replace(
    EvaluateConfig.from_params(PARAMS),
    metric="cosine",
    extra_metrics=("cityblock",),
    matchers=("single", "sequence"),
    confidence="ratio",
    ratio_exclusion=2,
    tolerance_frames=0,
    tolerance_m=10.0,
)
SEQUENCE = sequence_config()
# the raw section, as params.yaml holds it
EVALUATE_DICT = {
    **PARAMS["evaluate"],
    "metric": "cosine",
    "extra_metrics": ["cityblock"],
    "matchers": ["single", "sequence"],
    "confidence": "ratio",
    "ratio_exclusion": 2,
    "tolerance_frames": 0,
}


def test_evaluations_name_every_metric_and_matcher():
    evaluate = EVALUATE
    assert EvaluateConfig.from_params({"evaluate": EVALUATE_DICT}) == EVALUATE
    assert evaluations(evaluate) == [
        ("cosine", "single", ""),
        ("cosine", "sequence", "+seq"),
        ("cityblock", "single", "@cityblock"),
        ("cityblock", "sequence", "@cityblock+seq"),
    ]
    assert result_suffix("cityblock", "sequence", evaluate) == "@cityblock+seq"
    assert evaluations(replace(EVALUATE, extra_metrics=())) == [
        ("cosine", "single", ""),
        ("cosine", "sequence", "+seq"),
    ]


@pytest.mark.parametrize(
    "change, message",
    [
        ({"metric": "x"}, "evaluate.metric: unknown value 'x' (known: cosine, euclidean, cityblock)"),
        ({"extra_metrics": "cityblock"}, "evaluate.extra_metrics: expected a list"),
        ({"extra_metrics": ["manhattan"]}, "evaluate.extra_metrics: unknown value 'manhattan'"),
        ({"extra_metrics": ["cosine"]}, "evaluate.extra_metrics: 'cosine' is already evaluate.metric"),
        ({"matchers": ["single", "single"]}, "evaluate.matchers: repeated entry"),
        ({"confidence": "sharpness"}, "evaluate.confidence: unknown value 'sharpness' (known: distance, ratio)"),
        ({"ratio_exclusion": -1}, "evaluate.ratio_exclusion: expected an integer >= 0"),
        ({"ratio_exclusion": 2.5}, "evaluate.ratio_exclusion: expected an integer >= 0"),
    ],
)
def test_a_bad_section_is_checked_by_the_schema_naming_the_key(change, message):
    # the schema (and, for a choice among a registry's names, the registry) is the one check
    from seasonloop.registries.choices import check_params

    with pytest.raises(ValueError) as error:
        check_params({"evaluate": {**EVALUATE_DICT, **change}}, ["evaluate"])
    assert message in str(error.value) and "\n" not in str(error.value)


def test_the_matcher_registry():
    assert list(MATCHERS) == list(MATCHER_REGISTRY) and MATCHERS == {
        "single": "",
        "sequence": "+seq",
        "delta": "+delta",
        "smoothed": "+smoothed",
    }
    with pytest.raises(ValueError) as error:
        get_matcher("seq")
    assert str(error.value) == "evaluate.matchers: unknown matcher 'seq' (known: single, sequence, delta, smoothed)"
    with pytest.raises(ValueError, match="evaluate.matchers: unknown matcher 'seq'"):
        match_distances(np.ones((3, 3)), aligned_truth(np.arange(3), np.arange(3), 0), "seq", EVALUATE, SEQUENCE)


@pytest.mark.parametrize("matcher", list(MATCHER_REGISTRY))
def test_every_registered_matcher_evaluates_a_pair(matcher):
    rng = np.random.default_rng(2)
    places = np.arange(12)
    database = rng.normal(size=(12, 6))
    queries = database + 0.05 * rng.normal(size=(12, 6))
    distances = distance_matrix(database, queries, metric=EVALUATE.metric)
    metrics, pr, matched = match_distances(distances, aligned_truth(places, places, 0), matcher, EVALUATE, SEQUENCE)
    assert matched.shape == (12, 12) and len(pr) > 0 and 0 <= metrics["fraction_correct"] <= 1


def test_sequence_matching_of_a_pair_restarts_at_the_breaks_of_its_places():
    rng = np.random.default_rng(0)
    places = np.array([0, 1, 2, 3, 20, 21, 22, 23, 24, 50, 51, 52])
    distances = rng.random((12, 12))
    _, _, matched = match_distances(distances, aligned_truth(places, places, 0), "sequence", EVALUATE, SEQUENCE)
    np.testing.assert_array_equal(matched, sequence_distances(distances, 3, 1.0, 1.0, 1, 4, places, places))
    assert not np.array_equal(matched, sequence_distances(distances, 3, 1.0, 1.0, 1, 4))


def test_a_pair_is_matched_on_the_metric_asked_for():
    rng = np.random.default_rng(1)
    database, queries = rng.normal(size=(8, 4)), rng.normal(size=(8, 4))
    cosine = pair_distances(database, queries, "cosine")(slice(0, 8))
    l1 = pair_distances(database, queries, "cityblock")(slice(0, 8))
    np.testing.assert_allclose(l1, np.abs(queries[:, None] - database[None]).sum(-1), rtol=1e-6)
    assert cosine.max() <= 2.0 < l1.max()


def test_pr_landmarks_set_ours_beside_the_study():
    results = {
        "pca": {"summer-fall": {"recall_at_100_precision": 0.5, "precision_at_full_recall": 0.9}},
        "pca+seq": {"summer-fall": {"recall_at_100_precision": 1.0, "precision_at_full_recall": 1.0}},
    }
    landmarks = pr_landmarks(results)
    assert landmarks["summer-fall"]["pca"]["recall_at_100_precision"] == {"ours": 0.5, "study": 0.67}
    assert landmarks["summer-fall"]["ica"]["precision_at_full_recall"] == {"ours": None, "study": 0.9105}
    table = pr_landmarks_table(landmarks)
    assert table.loc[("summer-fall", "pca", "precision at 100% recall"), "ours"] == pytest.approx(90.0)
    assert table.loc[("summer-fall", "ica", "precision at 100% recall"), "study (S)"] == pytest.approx(91.05)
    assert np.isnan(table.loc[("summer-fall", "ica", "recall at 100% precision"), "ours"])


def test_cityblock_distances_are_the_same_on_any_number_of_threads(monkeypatch):
    rng = np.random.default_rng(3)
    database, queries = rng.normal(size=(40, 300)), rng.normal(size=(37, 300))
    monkeypatch.setenv("OMP_NUM_THREADS", "1")
    one = distance_matrix(database, queries, metric="cityblock")
    monkeypatch.setenv("OMP_NUM_THREADS", "3")
    assert np.array_equal(distance_matrix(database, queries, metric="cityblock"), one)
