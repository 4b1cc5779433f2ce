"""Place-recognition metrics: correct matches, the study's PR curve, recall@N, per-pair summary.

Which database places are correct for a query is the pair's ground truth
(seasonloop.data.ground_truth.PairTruth: aligned frame indices, positions or a matrix);
evaluate_pair is the aligned shorthand (frame i of every season is the same place). The place ids
of a test pair need not be contiguous because test sets drop tunnel and station frames.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from seasonloop.data.ground_truth import PairTruth, aligned_truth
from seasonloop.evaluation.records import RECALL_NS, QueryRecords, block_records, final_confidence, nearest_hits

if TYPE_CHECKING:
    import pandas as pd

METRIC_KEYS = (
    "fraction_correct",
    "precision_at_full_recall",
    "recall_at_100_precision",
    "auc_pr",
    "auc_pr_vpr_tutorial",
    "extended_precision",
    "recall_at_1",
    "recall_at_5",
    "recall_at_10",
    "n_queries",
    "n_database",
)


def _as_places(places, name: str) -> np.ndarray:
    """Validate a 1-D integer array of place ids (frame indices)."""
    places = np.asarray(places)
    if places.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of place ids, got shape {places.shape}")
    if not np.issubdtype(places.dtype, np.integer):
        raise ValueError(f"{name} must hold integer place ids (frame indices), got dtype {places.dtype}")
    return places.astype(np.int64)


def _check_tolerance(tolerance: int) -> int:
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, np.integer)) or tolerance < 0:
        raise ValueError(f"tolerance must be a non-negative integer number of frames, got {tolerance!r}")
    return int(tolerance)


def _check_distances(distances: np.ndarray, database_places: np.ndarray, query_places: np.ndarray) -> np.ndarray:
    distances = np.asarray(distances)
    if distances.ndim != 2 or distances.shape[0] == 0 or distances.shape[1] == 0:
        raise ValueError(f"distances must be a non-empty 2-D (N, M) array, got shape {distances.shape}")
    if distances.shape != (len(query_places), len(database_places)):
        raise ValueError(
            f"distances shape {distances.shape} does not match (len(query_places), len(database_places))"
            f" = ({len(query_places)}, {len(database_places)})"
        )
    return distances


def correct_matches(matched_places, query_places, tolerance: int) -> np.ndarray:
    """Boolean per query: |matched place - true place| <= tolerance (frames)."""
    matched_places = _as_places(matched_places, "matched_places")
    query_places = _as_places(query_places, "query_places")
    tolerance = _check_tolerance(tolerance)
    if matched_places.shape != query_places.shape:
        raise ValueError(f"matched_places has {matched_places.size} entries but query_places has {query_places.size}")
    return np.abs(matched_places - query_places) <= tolerance


def pr_curve(
    confidence: np.ndarray, correct: np.ndarray, has_match: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Precision-recall curve in the study's (Lowry & Milford) convention.

    One threshold per distinct confidence, from the highest down: the queries whose best match is at
    least that confident are accepted, tied queries together (so the curve does not depend on the
    order of the queries). TP = accepted and correct, FP = accepted and wrong, FN = queries not
    accepted (every query has a true match, so there are no true negatives; where `has_match` says
    a query has none, leaving it out is a true negative, not a FN). Returns (recall,
    precision), one entry per distinct confidence (N entries when no two queries tie).
    Recall = TP / (TP + FN) is 0 where TP = 0 (including 0/0 at the last threshold when every match
    is wrong); otherwise recall is 1 at the last threshold, where every query is accepted and
    precision equals the fraction of correct matches.
    """
    confidence = np.asarray(confidence, dtype=np.float64)
    correct = np.asarray(correct)
    if confidence.ndim != 1 or confidence.size == 0:
        raise ValueError(f"confidence must be a non-empty 1-D array, got shape {confidence.shape}")
    if correct.shape != confidence.shape:
        raise ValueError(f"correct has shape {correct.shape} but confidence has shape {confidence.shape}")
    if correct.dtype != np.bool_:
        raise ValueError(f"correct must be a boolean array, got dtype {correct.dtype}")
    if np.isnan(confidence).any():
        raise ValueError("confidence contains NaN values")
    has_match = np.ones(confidence.shape, bool) if has_match is None else np.asarray(has_match, bool)

    order = np.argsort(-confidence, kind="stable")
    sorted_confidence = confidence[order]
    # The last query of each run of equal confidences: accepting up to it accepts the whole tie.
    threshold_ends = np.flatnonzero(np.append(sorted_confidence[1:] != sorted_confidence[:-1], True))
    true_positives = np.cumsum(correct[order], dtype=np.int64)[threshold_ends]
    accepted = threshold_ends + 1
    positives_accepted = np.cumsum(has_match[order], dtype=np.int64)[threshold_ends]
    false_negatives = int(has_match.sum()) - positives_accepted
    precision = true_positives / accepted
    found = true_positives + false_negatives
    recall = np.divide(true_positives, found, out=np.zeros(accepted.size), where=true_positives > 0)
    return recall, precision


def auc_pr_vpr_tutorial(
    confidence: np.ndarray, correct: np.ndarray, n_thresholds: int = 100, n_positives: int | None = None
) -> float:
    """Area under the PR curve as VPR_Tutorial (Schubert et al. 2023, evaluation/metrics.py
    createPR with single-best-match, then np.trapz(P, R)) computes it.

    Its convention differs from the study's: recall = TP / N, N the queries that have a true match
    (n_positives, default all; a wrong accepted match is a missed
    true match, so recall ends at the fraction correct, not at 1), the curve starts at (recall 0,
    precision 1), and precision/recall are taken at n_thresholds confidence thresholds evenly
    spaced from the highest confidence to the lowest; the area is the trapezoidal rule.
    """
    confidence = np.asarray(confidence, dtype=np.float64)
    correct = np.asarray(correct, dtype=bool)
    # -inf/+inf confidences would make the evenly spaced thresholds NaN.
    if not np.isfinite(confidence).all():
        raise ValueError("auc_pr_vpr_tutorial needs finite confidences")
    thresholds = np.linspace(confidence.max(), confidence.min(), n_thresholds)
    accepted = confidence[None, :] >= thresholds[:, None]
    true_positives = (accepted & correct[None, :]).sum(axis=1)
    precision = np.concatenate(([1.0], true_positives / accepted.sum(axis=1)))
    positives = confidence.size if n_positives is None else max(1, int(n_positives))
    recall = np.concatenate(([0.0], true_positives / positives))
    return float(np.trapezoid(precision, recall))


def extended_precision(confidence: np.ndarray, correct: np.ndarray) -> float:
    """Extended Precision (Ferrarini et al., RA-L 2020) as VPR-Bench computes it
    (performance_comparison.py compute_extendedprecision over sklearn's precision_recall_curve of
    each query's best match, labelled correct or not, scored by its confidence):
    (P_R0 + R_P100) / 2, where P_R0 is the precision at the highest confidence (the queries tied
    at it accepted together: sklearn's thresholds are the distinct scores) and R_P100 the largest
    recall at which precision is still 1, 0 when P_R0 < 1. Recall here is VPR-Bench's: correct
    matches accepted / correct matches in all (not / queries, as pr_curve's), so R_P100 is 1
    when every correct match is more confident than every wrong one. 0 when no match is correct.
    """
    confidence = np.asarray(confidence, dtype=np.float64)
    correct = np.asarray(correct, dtype=bool)
    order = np.argsort(-confidence, kind="stable")
    sorted_confidence = confidence[order]
    threshold_ends = np.flatnonzero(np.append(sorted_confidence[1:] != sorted_confidence[:-1], True))
    true_positives = np.cumsum(correct[order], dtype=np.int64)[threshold_ends]
    precision = true_positives / (threshold_ends + 1)
    n_correct = int(correct.sum())
    if n_correct == 0 or precision[0] < 1.0:
        return float(precision[0]) / 2
    perfect = precision == 1.0  # a prefix: once a wrong match is accepted precision stays < 1
    return float(precision[0] + true_positives[perfect][-1] / n_correct) / 2


def recall_at_n(
    distances: np.ndarray, database_places, query_places, tolerance: int, ns: Sequence[int] = (1, 5, 10)
) -> dict[int, float]:
    """Fraction of queries with a database image within tolerance among their N nearest, per N
    (aligned places; truth_recall_at_n for any ground truth)."""
    database_places = _as_places(database_places, "database_places")
    query_places = _as_places(query_places, "query_places")
    tolerance = _check_tolerance(tolerance)
    distances = _check_distances(distances, database_places, query_places)
    return truth_recall_at_n(distances, aligned_truth(database_places, query_places, tolerance), ns)


def truth_recall_at_n(distances: np.ndarray, truth: PairTruth, ns: Sequence[int] = RECALL_NS) -> dict[int, float]:
    """Fraction of the queries that have a correct database place with one among their N nearest,
    per N; queries without any correct place are left out, as VPR_Tutorial's recallAtK does (0.0
    when no query has one). N larger than the database size is capped at the database size; ties
    as seasonloop.evaluation.records.nearest_hits."""
    distances = _check_distances(distances, truth.database_places, truth.query_places)
    ns = [int(n) for n in ns]
    if not ns or min(ns) < 1:
        raise ValueError(f"ns must be a non-empty sequence of integers >= 1, got {ns}")
    hits = nearest_hits(distances, truth.correct, min(max(ns), distances.shape[1]))
    return _recalls(hits[truth.has_match], ns, distances.shape[1])


def _recalls(hit_within: np.ndarray, ns: Sequence[int], n_database: int) -> dict[int, float]:
    if hit_within.shape[0] == 0:
        return {n: 0.0 for n in ns}
    return {n: float(hit_within[:, min(n, n_database) - 1].mean()) for n in ns}


def evaluate_pair(
    distances: np.ndarray,
    database_places,
    query_places,
    tolerance: int,
    confidence: str = "distance",
    ratio_exclusion: int = 0,
) -> tuple[dict[str, float | int], pd.DataFrame]:
    """evaluate_truth with aligned places: correct within `tolerance` frames of the query's place."""
    database_places = _as_places(database_places, "database_places")
    query_places = _as_places(query_places, "query_places")
    tolerance = _check_tolerance(tolerance)
    distances = _check_distances(distances, database_places, query_places)
    truth = aligned_truth(database_places, query_places, tolerance)
    return evaluate_truth(distances, truth, confidence, ratio_exclusion)


def truth_matches(
    distances: np.ndarray, truth: PairTruth, confidence: str = "distance", ratio_exclusion: int = 0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(best database column, its confidence, correct or not) per query, under the truth.

    confidence and ratio_exclusion (in place ids) go to seasonloop.evaluation.distances.best_matches.
    Cells the truth ignores (soft ground truth) are never picked. A query whose places are all soft
    has no match to pick: as VPR_Tutorial (soft cells set to the lowest similarity) it counts as a
    wrong match at the lowest confidence (seasonloop.evaluation.records.final_confidence).
    """
    distances = _check_distances(distances, truth.database_places, truth.query_places)
    records = block_records(distances, truth, confidence, ratio_exclusion)
    return records.best, final_confidence(records, confidence), records.correct


def evaluate_truth(
    distances: np.ndarray, truth: PairTruth, confidence: str = "distance", ratio_exclusion: int = 0
) -> tuple[dict[str, float | int], pd.DataFrame]:
    """Summary metrics and the PR curve of one test pair from its (N queries, M database) distances
    and its ground truth: summarise_records of the whole matrix as one block."""
    distances = _check_distances(distances, truth.database_places, truth.query_places)
    return summarise_records(block_records(distances, truth, confidence, ratio_exclusion), truth, confidence)


def summarise_records(
    records: QueryRecords, truth: PairTruth, confidence: str
) -> tuple[dict[str, float | int], pd.DataFrame]:
    """Summary metrics and the PR curve of one test pair from the records of all its queries.

    Metrics (keys in METRIC_KEYS): fraction_correct of best matches, in [0, 1];
    precision_at_full_recall (precision with every query accepted); recall_at_100_precision
    (largest recall at which precision is still 1.0, 0 if the most confident matches are wrong);
    auc_pr, the trapezoidal area (as sklearn.metrics.auc) under the study-convention curve (pr_curve:
    recall reaches 1) with a leading point at recall 0 that carries the precision of the first
    threshold; auc_pr_vpr_tutorial, the same area in VPR_Tutorial's convention (recall = TP / N,
    ending at the fraction of matchable queries matched correctly; see auc_pr_vpr_tutorial), so at
    most recall_at_1; extended_precision, VPR-Bench's headline metric (extended_precision); recall_at_1/5/10 over the queries that have a correct place (as VPR_Tutorial;
    fraction_correct counts every query, so the two differ when some have none; an all-soft query
    has none); n_queries; n_database. The PR DataFrame has columns recall, precision (one row per
    distinct confidence).
    """
    return summarise_queries(records, truth.has_match, len(truth.database_places), confidence)


def summarise_queries(
    records: QueryRecords, has_match: np.ndarray, n_database: int, confidence: str
) -> tuple[dict[str, float | int], pd.DataFrame]:
    """summarise_records of queries matched against databases of n_database places (the largest,
    when the queries of several folds were each matched against their own), which of them have a
    correct place given by has_match."""
    match_confidence, correct = final_confidence(records, confidence), records.correct
    has_match = np.asarray(has_match, bool)
    recall, precision = pr_curve(match_confidence, correct, has_match)

    perfect = precision == 1.0  # a prefix: once a wrong match is accepted precision stays < 1
    recall_at_100_precision = float(recall[perfect].max()) if perfect.any() else 0.0
    # The curve starts at recall TP/N > 0; extend its first precision to recall 0.
    # recall never decreases along the curve, so this is sklearn.metrics.auc's area (its trapezoid),
    # without importing scikit-learn (1.4 s at every evaluate stage's start)
    auc_pr = float(np.trapezoid(np.concatenate(([precision[0]], precision)), np.concatenate(([0.0], recall))))
    recalls = _recalls(records.hit_within[has_match], RECALL_NS, n_database)

    metrics: dict[str, float | int] = {
        "fraction_correct": float(correct.mean()),
        "precision_at_full_recall": float(precision[-1]),
        "recall_at_100_precision": recall_at_100_precision,
        "auc_pr": auc_pr,
        "auc_pr_vpr_tutorial": auc_pr_vpr_tutorial(match_confidence, correct, n_positives=int(has_match.sum())),
        "extended_precision": extended_precision(match_confidence, correct),
        "recall_at_1": recalls[1],
        "recall_at_5": recalls[5],
        "recall_at_10": recalls[10],
        "n_queries": len(records.correct),
        "n_database": n_database,
    }
    import pandas as pd  # here, not at the top: the params check imports this module and needs no pandas

    return metrics, pd.DataFrame({"recall": recall, "precision": precision})
