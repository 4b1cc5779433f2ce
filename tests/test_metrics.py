"""Tests for seasonloop.evaluation.metrics on hand-worked examples."""

import numpy as np
import pytest

from seasonloop.evaluation.metrics import (
    METRIC_KEYS,
    auc_pr_vpr_tutorial,
    correct_matches,
    evaluate_pair,
    extended_precision,
    pr_curve,
    recall_at_n,
)

# Five queries q0..q4 in input order; sorted by confidence: q1, q3, q0, q4, q2 -> T, T, F, T, F.
CONFIDENCE = np.array([0.7, 0.9, 0.5, 0.8, 0.6])
CORRECT = np.array([False, True, False, True, True])
# k | TP FP FN | precision = TP/k | recall = TP/(TP+FN)
# 1 |  1  0  4 | 1                | 1/5 = 0.2
# 2 |  2  0  3 | 1                | 2/5 = 0.4
# 3 |  2  1  2 | 2/3              | 2/4 = 0.5
# 4 |  3  1  1 | 3/4              | 3/4 = 0.75
# 5 |  3  2  0 | 3/5              | 3/3 = 1.0
EXPECTED_RECALL = [0.2, 0.4, 0.5, 0.75, 1.0]
EXPECTED_PRECISION = [1.0, 1.0, 2 / 3, 0.75, 0.6]
# Trapezoids from the leading point (0, 1): 0.2 + 0.2 + 0.1*(1+2/3)/2 + 0.25*(2/3+3/4)/2
# + 0.25*(3/4+3/5)/2 = 0.4 + 0.0833333 + 0.1770833 + 0.16875
EXPECTED_AUC = 0.4 + 0.1 * (1 + 2 / 3) / 2 + 0.25 * (2 / 3 + 0.75) / 2 + 0.25 * (0.75 + 0.6) / 2


def test_pr_curve_hand_example():
    recall, precision = pr_curve(CONFIDENCE, CORRECT)
    np.testing.assert_allclose(recall, EXPECTED_RECALL)
    np.testing.assert_allclose(precision, EXPECTED_PRECISION)
    # At k = N: recall 1, precision = fraction correct.
    assert recall[-1] == 1.0
    assert precision[-1] == pytest.approx(CORRECT.mean())


def test_pr_curve_accepts_tied_confidences_together():
    # All tied: one threshold accepts all three at once (precision 2/3), whatever their order.
    recall, precision = pr_curve(np.zeros(3), np.array([False, True, True]))
    np.testing.assert_allclose(precision, [2 / 3])
    np.testing.assert_allclose(recall, [1.0])
    # Thresholds 1, 0.5 (two tied queries, one right), 0.2: accepted 1, 3, 4.
    confidence, correct = np.array([1.0, 0.5, 0.5, 0.2]), np.array([True, False, True, False])
    recall, precision = pr_curve(confidence, correct)
    np.testing.assert_allclose(precision, [1.0, 2 / 3, 0.5])
    np.testing.assert_allclose(recall, [1 / 4, 2 / 3, 1.0])  # TP / (TP + not accepted)
    swapped = pr_curve(confidence[[0, 2, 1, 3]], correct[[0, 2, 1, 3]])
    np.testing.assert_array_equal(swapped[0], recall)
    np.testing.assert_array_equal(swapped[1], precision)


def test_auc_pr_vpr_tutorial_hand_example():
    # Thresholds evenly spaced 0.9..0.5; points (0, 1) (0.2, 1) (0.4, 1) (0.4, 2/3) (0.6, 3/4)
    # (0.6, 3/5), recall = TP / 5: area 0.2 + 0.2 + 0.2 * (2/3 + 3/4) / 2.
    assert auc_pr_vpr_tutorial(CONFIDENCE, CORRECT) == pytest.approx(0.4 + 0.1 * (2 / 3 + 0.75))
    # Recall ends at the fraction correct, so the area is at most that; the study's reaches 1.
    assert auc_pr_vpr_tutorial(CONFIDENCE, CORRECT) <= CORRECT.mean()


def test_pr_curve_all_wrong_is_zero():
    recall, precision = pr_curve(np.array([3.0, 2.0, 1.0]), np.zeros(3, dtype=bool))
    np.testing.assert_array_equal(recall, 0.0)
    np.testing.assert_array_equal(precision, 0.0)


def test_pr_curve_bad_inputs_raise():
    with pytest.raises(ValueError, match="boolean"):
        pr_curve(CONFIDENCE, CORRECT.astype(int))
    with pytest.raises(ValueError, match="shape"):
        pr_curve(CONFIDENCE, CORRECT[:3])
    with pytest.raises(ValueError, match="NaN"):
        pr_curve(np.array([np.nan, 1.0]), np.array([True, False]))


def test_correct_matches_uses_place_ids_not_positions():
    # Non-contiguous place ids: tolerance is measured in frames.
    matched = np.array([4, 9, 20, 62])
    true = np.array([3, 10, 9, 60])
    np.testing.assert_array_equal(correct_matches(matched, true, 0), [False, False, False, False])
    np.testing.assert_array_equal(correct_matches(matched, true, 1), [True, True, False, False])
    np.testing.assert_array_equal(correct_matches(matched, true, 2), [True, True, False, True])
    with pytest.raises(ValueError, match="tolerance"):
        correct_matches(matched, true, -1)
    with pytest.raises(ValueError, match="integer"):
        correct_matches(matched.astype(float), true, 1)


DATABASE_PLACES = np.array([3, 4, 9, 20, 40, 60, 61, 62, 63, 64, 65, 66])
QUERY_PLACES = np.array([3, 4, 9, 20, 40])


def hand_distances() -> np.ndarray:
    """Best distances q1 0.1 (right), q3 0.2 (right), q0 0.3 (place 4 for 3), q4 0.4 (right),
    q2 0.5 (place 40 for 9) -> with confidence -distance the same T, T, F, T, F order as above."""
    distances = np.ones((5, 12))
    distances[0, 1], distances[0, 0] = 0.3, 0.35  # q0: true place second nearest
    distances[1, 1] = 0.1
    distances[2, 4] = 0.5
    distances[2, 5:11] = [0.6, 0.61, 0.62, 0.63, 0.64, 0.65]
    distances[2, 2] = 0.9  # q2: true place eighth nearest
    distances[3, 3] = 0.2
    distances[4, 4] = 0.4
    return distances


def test_evaluate_pair_hand_example():
    metrics, pr = evaluate_pair(hand_distances(), DATABASE_PLACES, QUERY_PLACES, tolerance=0)
    assert tuple(metrics) == METRIC_KEYS
    assert metrics["fraction_correct"] == pytest.approx(0.6)
    assert metrics["precision_at_full_recall"] == pytest.approx(0.6)
    assert metrics["recall_at_100_precision"] == pytest.approx(0.4)
    assert metrics["auc_pr"] == pytest.approx(EXPECTED_AUC)
    assert metrics["auc_pr_vpr_tutorial"] == pytest.approx(0.4 + 0.1 * (2 / 3 + 0.75))
    # T T F T F: precision 1 at the top, 2 of the 3 correct matches before the first wrong one
    assert metrics["extended_precision"] == pytest.approx((1 + 2 / 3) / 2)
    # @1: q1 q3 q4; @5: + q0 (rank 2); @10: + q2 (rank 8)
    assert metrics["recall_at_1"] == pytest.approx(0.6)
    assert metrics["recall_at_5"] == pytest.approx(0.8)
    assert metrics["recall_at_10"] == pytest.approx(1.0)
    assert (metrics["n_queries"], metrics["n_database"]) == (5, 12)
    assert list(pr.columns) == ["recall", "precision"]
    np.testing.assert_allclose(pr["recall"], EXPECTED_RECALL)
    np.testing.assert_allclose(pr["precision"], EXPECTED_PRECISION)


def test_evaluate_pair_tolerance_in_frames():
    # Tolerance 2: q0 (4 for 3) becomes right; q2 (40 for 9, two columns away) stays wrong.
    metrics, pr = evaluate_pair(hand_distances(), DATABASE_PLACES, QUERY_PLACES, tolerance=2)
    assert metrics["fraction_correct"] == pytest.approx(0.8)
    # Order T, T, T, T, F: precision 1 up to k=4, recall there 4/(4+1).
    assert metrics["recall_at_100_precision"] == pytest.approx(0.8)
    assert metrics["recall_at_1"] == pytest.approx(0.8)


def test_evaluate_pair_most_confident_wrong():
    distances = hand_distances()
    distances[0, 1] = 0.01  # q0's wrong match becomes the most confident
    metrics, _ = evaluate_pair(distances, DATABASE_PLACES, QUERY_PLACES, tolerance=0)
    assert metrics["recall_at_100_precision"] == 0.0


def test_evaluate_pair_ratio_confidence():
    metrics, pr = evaluate_pair(hand_distances(), DATABASE_PLACES, QUERY_PLACES, 0, confidence="ratio")
    # Runner-up / best: q0 0.35/0.3, q1 10, q2 0.6/0.5, q3 5, q4 2.5 -> order q1, q3, q4, q2, q0
    # = T, T, T, F, F (the confidence is 1 - best / runner-up, which ranks the same)
    np.testing.assert_allclose(pr["precision"], [1.0, 1.0, 1.0, 0.75, 0.6])
    assert metrics["recall_at_100_precision"] == pytest.approx(3 / 5)


def test_evaluate_pair_shape_mismatch_raises():
    with pytest.raises(ValueError, match="does not match"):
        evaluate_pair(hand_distances(), DATABASE_PLACES[:-1], QUERY_PLACES, tolerance=0)


@pytest.mark.parametrize("tolerance", [0, 2])
def test_recall_at_n_random(tolerance):
    rng = np.random.default_rng(1)
    places = np.sort(rng.choice(1000, size=60, replace=False))  # non-contiguous ids
    distances = rng.random((60, 60))
    distances[np.arange(60), np.arange(60)] -= 0.3 * rng.random(60)
    recalls = recall_at_n(distances, places, places, tolerance, ns=(1, 2, 5, 10, 60, 100))
    values = list(recalls.values())
    assert all(a <= b for a, b in zip(values, values[1:]))
    assert recalls[60] == 1.0 and recalls[100] == 1.0  # N >= database size: every query hits
    metrics, _ = evaluate_pair(distances, places, places, tolerance)
    assert 0.0 < metrics["fraction_correct"] < 1.0
    assert recalls[1] == pytest.approx(metrics["fraction_correct"])
    assert metrics["recall_at_1"] == pytest.approx(metrics["fraction_correct"])


def test_recall_at_n_bad_ns_raises():
    with pytest.raises(ValueError, match="ns"):
        recall_at_n(hand_distances(), DATABASE_PLACES, QUERY_PLACES, 0, ns=(0,))


def test_auc_pr_is_scikit_learns_area_bit_for_bit():
    # evaluate_pair integrates with numpy's trapezoid instead of importing scikit-learn: same number
    from sklearn.metrics import auc

    from seasonloop.evaluation.distances import best_matches

    rng = np.random.default_rng(4)
    for _ in range(20):
        distances = rng.random((30, 40))
        places = np.arange(30)
        metrics, _ = evaluate_pair(distances, np.arange(40), places, tolerance=0)
        columns, confidence = best_matches(distances, "distance", np.arange(40), 10)
        recall, precision = pr_curve(confidence, columns == places)
        assert np.all(np.diff(recall) >= 0)
        expected = float(auc(np.concatenate(([0.0], recall)), np.concatenate(([precision[0]], precision))))
        assert metrics["auc_pr"] == expected


def vpr_bench_extended_precision(correct: np.ndarray, confidence: np.ndarray) -> float:
    """VPR-Bench's performance_comparison.py: compute_precision_recall then compute_extendedprecision."""
    from sklearn.metrics import precision_recall_curve

    precision, recall, _ = precision_recall_curve(correct.astype(int), confidence)
    precision_at_recall_zero = precision[-2]
    if precision_at_recall_zero < 1:
        recall_at_precision_one = 0
    else:
        recall_at_precision_one = recall[min(np.argwhere(precision == 1))]
    return float(np.squeeze((precision_at_recall_zero + recall_at_precision_one) / 2))


def test_extended_precision_is_vpr_benchs_on_random_cases_with_ties():
    rng = np.random.default_rng(5)
    checked = 0
    for case in range(300):
        n = int(rng.integers(2, 40))
        # few distinct confidences in some cases: ties, which VPR-Bench accepts together
        confidence = rng.integers(0, 4 if case % 3 == 0 else 1000, n).astype(float)
        correct = rng.random(n) < rng.uniform(0.05, 0.95)
        if case % 5 == 0:  # the most confident matches right: R_P100 > 0
            correct[np.argsort(-confidence, kind="stable")[: n // 3]] = True
        if not correct.any() or len(np.unique(confidence)) < 2:
            continue  # sklearn's recall is 0/0 there; VPR-Bench has no value to compare
        assert extended_precision(confidence, correct) == pytest.approx(
            vpr_bench_extended_precision(correct, confidence), abs=1e-12
        ), (confidence, correct)
        checked += 1
    assert checked > 200


def test_extended_precision_hand_cases():
    # most confident first: T T F T -> P_R0 = 1, precision 1 up to 2 of the 3 correct matches
    assert extended_precision(np.array([4.0, 3.0, 2.0, 1.0]), np.array([True, True, False, True])) == pytest.approx(
        (1 + 2 / 3) / 2
    )
    # the most confident match wrong: R_P100 = 0, EP = P_R0 / 2
    assert extended_precision(np.array([4.0, 3.0]), np.array([False, True])) == 0.0
    # a tie at the top: both accepted together, precision 1/2
    assert extended_precision(np.array([4.0, 4.0, 1.0]), np.array([True, False, True])) == pytest.approx(0.25)
    assert extended_precision(np.array([2.0, 1.0]), np.array([False, False])) == 0.0
