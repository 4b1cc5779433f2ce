"""Tests for seasonloop.evaluation.distances."""

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from seasonloop.evaluation.distances import CONFIDENCES, DISTANCES, best_matches, distance_matrix


@pytest.fixture
def descriptors():
    rng = np.random.default_rng(0)
    return rng.normal(size=(7, 5)), rng.normal(size=(4, 5))


@pytest.mark.parametrize("metric", ["cosine", "euclidean", "cityblock"])
def test_distance_matrix_matches_scipy(descriptors, metric):
    database, queries = descriptors
    distances = distance_matrix(database, queries, metric=metric)
    assert distances.shape == (4, 7)
    assert distances.dtype == np.float32
    np.testing.assert_allclose(distances, cdist(queries, database, metric=metric), rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("metric", ["cosine", "euclidean", "cityblock"])
def test_batching_does_not_change_result(descriptors, metric):
    database, queries = descriptors
    whole = distance_matrix(database, queries, metric=metric)
    batched = distance_matrix(database, queries, metric=metric, batch_size=3)
    np.testing.assert_array_equal(whole, batched)


def test_only_cityblock_changes_under_a_rotation(descriptors):
    database, queries = descriptors
    rotation, _ = np.linalg.qr(np.random.default_rng(1).normal(size=(5, 5)))
    for metric in ("cosine", "euclidean", "cityblock"):
        before = distance_matrix(database, queries, metric=metric)
        after = distance_matrix(database @ rotation, queries @ rotation, metric=metric)
        if metric == "cityblock":
            assert np.abs(after - before).max() > 0.1
        else:
            np.testing.assert_allclose(after, before, atol=1e-6)


def test_zero_vector_cosine_is_finite():
    database = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    queries = np.array([[0.0, 0.0], [3.0, 0.0]])
    distances = distance_matrix(database, queries, metric="cosine")
    assert np.isfinite(distances).all()
    # A zero vector is orthogonal to everything: distance 1.
    np.testing.assert_allclose(distances[0], [1.0, 1.0, 1.0])
    np.testing.assert_allclose(distances[1], [1.0, 0.0, 1.0], atol=1e-7)


def test_euclidean_identical_large_vectors_is_zero():
    vectors = np.full((2, 64), 1e4) + np.arange(64)
    distances = distance_matrix(vectors, vectors, metric="euclidean")
    assert np.all(distances >= 0)
    np.testing.assert_allclose(np.diag(distances), 0.0, atol=1e-2)


def test_bad_inputs_raise(descriptors):
    database, queries = descriptors
    with pytest.raises(ValueError, match="manhattan"):
        distance_matrix(database, queries, metric="manhattan")
    with pytest.raises(ValueError, match="dimension"):
        distance_matrix(database, queries[:, :3])
    with pytest.raises(ValueError, match="NaN"):
        distance_matrix(database, np.full((1, 5), np.nan))
    with pytest.raises(ValueError, match="batch_size"):
        distance_matrix(database, queries, batch_size=0)


def test_best_matches_known_matrix():
    distances = np.array([[0.5, 0.1, 0.9], [0.3, 0.6, 0.2], [0.0, 0.4, 0.8], [0.0, 0.0, 0.7]])
    columns, confidence = best_matches(distances, confidence="distance")
    np.testing.assert_array_equal(columns, [1, 2, 0, 0])  # tie in the last row -> lowest column
    np.testing.assert_allclose(confidence, [-0.1, -0.2, -0.0, -0.0])

    columns, ratio = best_matches(distances, confidence="ratio")
    np.testing.assert_array_equal(columns, [1, 2, 0, 0])
    # 1 - best/runner-up: 1 - 0.1/0.5, 1 - 0.2/0.3; best 0 with runner-up 0.4 -> 1 (not +inf);
    # both 0 -> 0 (not distinctive)
    np.testing.assert_allclose(ratio, [0.8, 1 / 3, 1.0, 0.0])
    assert np.isfinite(ratio).all()


def test_ratio_runner_up_lies_outside_the_exclusion_window_in_place_ids():
    # Places 10..14 then a jump to 40, 41 (a break): the window is in place ids, not columns.
    places = np.array([10, 11, 12, 13, 14, 40, 41])
    distances = np.array([[0.9, 0.2, 0.1, 0.15, 0.5, 0.4, 0.8]])
    _, no_window = best_matches(distances, "ratio", places, exclusion=0)
    np.testing.assert_allclose(no_window, [1 - 0.1 / 0.15])  # the neighbour at place 13
    _, window = best_matches(distances, "ratio", places, exclusion=2)
    np.testing.assert_allclose(window, [1 - 0.1 / 0.4])  # places 10..14 excluded; place 40 is next
    with pytest.raises(ValueError, match="more than 40 places"):
        best_matches(distances, "ratio", places, exclusion=40)
    with pytest.raises(ValueError, match="exclusion"):
        best_matches(distances, "ratio", places, exclusion=-1)
    # An infinite runner-up (sequence scores with no trajectory) is perfectly distinctive, not NaN.
    _, infinite = best_matches(np.array([[0.3, np.inf]]), "ratio")
    np.testing.assert_array_equal(infinite, [1.0])


def test_best_matches_bad_inputs_raise():
    with pytest.raises(ValueError, match="sharpness"):
        best_matches(np.ones((2, 2)), confidence="sharpness")
    with pytest.raises(ValueError, match="non-negative"):
        best_matches(np.array([[-1.0, 0.5]]), confidence="ratio")
    with pytest.raises(ValueError, match="database place more than 0 places"):
        best_matches(np.ones((3, 1)), confidence="ratio")
    with pytest.raises(ValueError, match="NaN"):
        best_matches(np.array([[np.nan, 1.0]]))


@pytest.mark.parametrize("metric", list(DISTANCES))
def test_every_registered_metric_gives_non_negative_float32_distances(metric):
    rng = np.random.default_rng(4)
    database, queries = rng.normal(size=(7, 5)), rng.normal(size=(6, 5))
    distances = distance_matrix(database, queries, metric=metric, batch_size=4)
    assert distances.shape == (6, 7) and distances.dtype == np.float32 and (distances >= 0).all()
    # a query identical to a database row is nearest to it
    assert distance_matrix(database, database[[2]], metric=metric).argmin() == 2


@pytest.mark.parametrize("confidence", list(CONFIDENCES))
def test_every_registered_confidence_ranks_a_distinct_match_higher(confidence):
    distances = np.array([[0.1, 0.9, 0.95], [0.5, 0.55, 0.6]])
    columns, scores = best_matches(distances, confidence=confidence)
    assert list(columns) == [0, 0] and scores[0] > scores[1]


def test_unknown_metric_and_confidence_are_one_line_listing_the_known_names():
    for call, names in (
        (lambda: distance_matrix(np.ones((2, 2)), np.ones((2, 2)), metric="manhattan"), DISTANCES),
        (lambda: best_matches(np.ones((2, 2)), confidence="sharpness"), CONFIDENCES),
    ):
        with pytest.raises(ValueError) as error:
            call()
        assert "\n" not in str(error.value) and all(name in str(error.value) for name in names)
