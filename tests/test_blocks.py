"""A pair evaluated a block of query rows at a time gives the numbers of the whole matrix: the
matchers' blocks, the records and their summary, the thumbnail, the ground truth built by blocks."""

from __future__ import annotations

import numpy as np
import pytest
from sequence_settings import sequence_config

from seasonloop.data import ground_truth
from seasonloop.data.ground_truth import PairTruth, aligned_truth, position_truth
from seasonloop.evaluation.blocks import evaluate_in_blocks, pair_distances, similarity_thumbnail
from seasonloop.evaluation.distances import distance_matrix
from seasonloop.evaluation.matchers import match_distances
from seasonloop.evaluation.sequence import sequence_distance_blocks, sequence_distances
from seasonloop.params.settings import EvaluateConfig

SEQUENCE = sequence_config(length=4, v_min=0.8, v_max=1.2, v_steps=3, window_at_breaks="ignore")


def evaluate_config(confidence: str) -> EvaluateConfig:
    return EvaluateConfig(("a-b",), "cityblock", (), confidence, 2, 1, 10.0, ("single", "sequence"))


def pair(seed: int = 0, n: int = 37, m: int = 41):
    """Descriptors of a route with breaks in its place ids (a test set without tunnels), queries
    near their own place, and its aligned truth within 1 place."""
    rng = np.random.default_rng(seed)
    places = np.concatenate([np.arange(0, 20), np.arange(25, 25 + m - 20)])
    scene = rng.normal(size=(places.max() + 1, 8))
    database = scene[places] + 0.3 * rng.normal(size=(m, 8))
    query_places = places[:n]
    queries = scene[query_places] + 0.6 * rng.normal(size=(n, 8))
    return database, queries, aligned_truth(places, query_places, 1)


def with_soft(truth: PairTruth) -> PairTruth:
    """Soft cells beside the hard ones, and two queries whose places are all soft."""
    ignored = np.roll(truth.correct, 2, axis=1) & ~truth.correct
    ignored[[3, 30]] = True
    correct = truth.correct.copy()
    correct[[3, 30]] = False
    ignored &= ~correct
    exact = np.where(correct.any(axis=1), truth.exact, -1)
    return PairTruth("matrix", truth.database_places, truth.query_places, correct, exact, ignored)


@pytest.mark.parametrize("matcher", ["single", "sequence"])
@pytest.mark.parametrize("confidence", ["distance", "ratio"])
@pytest.mark.parametrize("soft", [False, True])
def test_blocks_give_the_whole_matrix_numbers(matcher, confidence, soft):
    database, queries, truth = pair()
    truth = with_soft(truth) if soft else truth
    distances = distance_matrix(database, queries, metric="cityblock")
    whole_metrics, whole_pr, matched = match_distances(distances, truth, matcher, evaluate_config(confidence), SEQUENCE)
    for rows_per_block in (1, 5, 36, 37, 100):
        evaluation = evaluate_in_blocks(
            lambda rows: distances[rows],
            len(database),
            truth,
            matcher,
            evaluate_config(confidence),
            SEQUENCE,
            rows_per_block,
        )
        assert evaluation.metrics == whole_metrics
        assert evaluation.pr.equals(whole_pr)
        np.testing.assert_array_equal(evaluation.thumbnail, similarity_thumbnail(matched))
        # the outcomes are the metrics' own: their means are the fraction correct and recall@1
        outcomes = evaluation.outcomes
        assert outcomes.correct.mean() == whole_metrics["fraction_correct"]
        assert outcomes.hit_at_1[outcomes.has_match].mean() == pytest.approx(whole_metrics["recall_at_1"])
        np.testing.assert_array_equal(outcomes.query_place, truth.query_places)


def test_sequence_blocks_read_the_history_before_them_and_the_whole_minimum():
    _, _, truth = pair(seed=1, n=41, m=41)
    rng = np.random.default_rng(2)
    distances = rng.uniform(size=(41, 41)).astype(np.float32)
    whole = sequence_distances(
        distances, 4, 0.8, 1.2, 3, 4, truth.query_places, truth.database_places, window_at_breaks="ignore"
    )
    for rows_per_block in (1, 3, 40):
        blocks = sequence_distance_blocks(
            lambda rows: distances[rows], 41, 41, rows_per_block, SEQUENCE, truth.query_places, truth.database_places
        )
        np.testing.assert_array_equal(np.concatenate([scores for _, scores in blocks]), whole)


def test_thumbnail_rows_stay_whole_when_the_pair_is_larger_than_the_thumbnail():
    rng = np.random.default_rng(3)
    places = np.arange(400)
    truth = aligned_truth(places, places, 0)
    distances = rng.uniform(size=(400, 400)).astype(np.float32)
    # 400 rows make thumbnail rows of 3: blocks of 100 rows are cut to 99
    thumbnail = evaluate_in_blocks(
        lambda rows: distances[rows], 400, truth, "single", evaluate_config("distance"), SEQUENCE, 100
    ).thumbnail
    np.testing.assert_array_equal(thumbnail, similarity_thumbnail(distances))


def test_pair_distances_by_blocks_are_the_whole_matrix_rows():
    database, queries, _ = pair()
    whole = distance_matrix(database, queries, metric="cityblock")
    blocked = pair_distances(database, queries, "cityblock", whole_max_bytes=0)  # never whole
    np.testing.assert_array_equal(np.concatenate([blocked(slice(s, s + 5)) for s in range(0, 37, 5)]), whole)


def test_truths_built_by_row_blocks_are_those_built_whole(monkeypatch):
    rng = np.random.default_rng(4)
    database_places, query_places = np.arange(0, 90, 2), np.arange(0, 90, 3)
    positions = rng.uniform(0, 200, size=(90, 2))
    whole = [
        aligned_truth(database_places, query_places, 2),
        position_truth(positions[database_places], positions[query_places], database_places, query_places, 30.0),
    ]
    monkeypatch.setattr(ground_truth, "TRUTH_ROWS_PER_BLOCK", 4)
    blocked = [
        aligned_truth(database_places, query_places, 2),
        position_truth(positions[database_places], positions[query_places], database_places, query_places, 30.0),
    ]
    for one, other in zip(whole, blocked):
        np.testing.assert_array_equal(one.correct, other.correct)
        np.testing.assert_array_equal(one.exact, other.exact)
