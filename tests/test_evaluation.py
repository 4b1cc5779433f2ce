"""Tests for seasonloop.evaluation (metric x matcher variants, param checks) and the PR landmarks."""

import numpy as np
import pytest

from seasonloop.evaluation import check_matching, evaluations, match_distances, match_pair
from seasonloop.sequence import sequence_distances
from seasonloop.summary import pr_landmarks, pr_landmarks_table

EVALUATE = {"metric": "cosine", "extra_metrics": ["cityblock"], "matchers": ["single", "sequence"],
            "confidence": "ratio", "ratio_exclusion": 2, "tolerance_frames": 0}
SEQUENCE = {"length": 3, "v_min": 1.0, "v_max": 1.0, "v_steps": 1, "window": 4}


def test_evaluations_name_every_metric_and_matcher():
    assert evaluations(EVALUATE) == [("cosine", "single", ""), ("cosine", "sequence", "+seq"),
                                     ("cityblock", "single", "@cityblock"),
                                     ("cityblock", "sequence", "@cityblock+seq")]
    assert evaluations({**EVALUATE, "extra_metrics": []}) == [("cosine", "single", ""), ("cosine", "sequence", "+seq")]


@pytest.mark.parametrize("change, message", [
    ({"metric": "x"}, "evaluate.metric must be one of cosine, euclidean, cityblock, got 'x'"),
    ({"extra_metrics": "cityblock"}, "evaluate.extra_metrics must be a list"),
    ({"extra_metrics": ["manhattan"]}, "evaluate.extra_metrics: unknown entry 'manhattan'"),
    ({"extra_metrics": ["cosine"]}, "evaluate.extra_metrics: 'cosine' is already evaluate.metric"),
    ({"matchers": ["single", "single"]}, "evaluate.matchers: repeated entry"),
])
def test_bad_variant_params_name_the_key(change, message):
    with pytest.raises(ValueError, match=message):
        evaluations({**EVALUATE, **change})


@pytest.mark.parametrize("change, message", [
    ({"confidence": "sharpness"}, "evaluate.confidence must be one of distance, ratio, got 'sharpness'"),
    ({"ratio_exclusion": -1}, "evaluate.ratio_exclusion must be an integer >= 0"),
    ({"ratio_exclusion": 2.5}, "evaluate.ratio_exclusion must be an integer >= 0"),
])
def test_bad_matching_params_name_the_key(change, message):
    with pytest.raises(ValueError, match=message):
        check_matching({**EVALUATE, **change})


def test_sequence_matching_of_a_pair_restarts_at_the_breaks_of_its_places():
    rng = np.random.default_rng(0)
    places = np.array([0, 1, 2, 3, 20, 21, 22, 23, 24, 50, 51, 52])
    distances = rng.random((12, 12))
    _, _, matched = match_distances(distances, places, places, "sequence", EVALUATE, SEQUENCE)
    np.testing.assert_array_equal(matched, sequence_distances(distances, 3, 1.0, 1.0, 1, 4, places, places))
    assert not np.array_equal(matched, sequence_distances(distances, 3, 1.0, 1.0, 1, 4))


def test_match_pair_uses_the_metric_asked_for():
    rng = np.random.default_rng(1)
    database, queries, places = rng.normal(size=(8, 4)), rng.normal(size=(8, 4)), np.arange(8)
    _, _, cosine = match_pair(database, queries, places, places, "single", EVALUATE, SEQUENCE)
    _, _, l1 = match_pair(database, queries, places, places, "single", EVALUATE, SEQUENCE, metric="cityblock")
    np.testing.assert_allclose(l1, np.abs(queries[:, None] - database[None]).sum(-1), rtol=1e-6)
    assert cosine.max() <= 2.0 < l1.max()


def test_pr_landmarks_set_ours_beside_the_study():
    results = {"pca": {"summer-fall": {"recall_at_100_precision": 0.5, "precision_at_full_recall": 0.9}},
               "pca+seq": {"summer-fall": {"recall_at_100_precision": 1.0, "precision_at_full_recall": 1.0}}}
    landmarks = pr_landmarks(results)
    assert landmarks["summer-fall"]["pca"]["recall_at_100_precision"] == {"ours": 0.5, "study": 0.67}
    assert landmarks["summer-fall"]["ica"]["precision_at_full_recall"] == {"ours": None, "study": 0.9105}
    table = pr_landmarks_table(landmarks)
    assert table.loc[("summer-fall", "pca", "precision at 100% recall"), "ours"] == pytest.approx(90.0)
    assert table.loc[("summer-fall", "ica", "precision at 100% recall"), "study (S)"] == pytest.approx(91.05)
    assert np.isnan(table.loc[("summer-fall", "ica", "recall at 100% precision"), "ours"])
