"""What every metric of a pair needs from each query, taken from a block of query rows of the
distances matched on: so a pair is evaluated a block of rows at a time (a 27,592 x 27,592 pair's
float32 distances are 3 GB) with the numbers the whole matrix gives (seasonloop.evaluation.metrics
summarises the records; evaluate_truth on a whole matrix is one block).

Every record of a query depends on its own row alone, but for one thing: a query whose database
places are all soft gets the pair's lowest confidence, which final_confidence sets once every block
is in.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from seasonloop.data.ground_truth import PairTruth
from seasonloop.evaluation.distances import best_matches

# recall@N is reported for these N; a record keeps the hits among the max(RECALL_NS) nearest
RECALL_NS = (1, 5, 10)


@dataclass(frozen=True)
class QueryRecords:
    """Per query: its best database column and the distance there, the match's confidence and correctness, which of its
    nearest columns are correct; and the largest finite distance of its rows."""

    best: np.ndarray  # (n,) int64: the best column (cells the truth ignores are never picked)
    distance: np.ndarray  # (n,) float64: the distance matched on at the best column
    confidence: np.ndarray  # (n,) float64, higher = more confident; all-soft queries: final_confidence
    correct: np.ndarray  # (n,) bool
    hit_within: np.ndarray  # (n, depth) bool: a correct column among the k + 1 nearest
    all_soft: np.ndarray  # (n,) bool: every database place of the query is soft
    largest_finite: float  # of the rows' distances (-inf when none is finite or the truth has no soft cells)

    _ARRAYS: ClassVar[tuple[str, ...]] = ("best", "distance", "confidence", "correct", "hit_within", "all_soft")

    @classmethod
    def concatenate(cls, parts: Sequence[QueryRecords]) -> QueryRecords:
        """The records of consecutive blocks of query rows as one."""
        arrays = {name: np.concatenate([getattr(part, name) for part in parts]) for name in cls._ARRAYS}
        return cls(**arrays, largest_finite=max(part.largest_finite for part in parts))


def mask_soft(distances: np.ndarray, truth: PairTruth) -> tuple[np.ndarray, np.ndarray]:
    """(distances with the cells the truth ignores at +inf, so they are never picked nor among the
    N nearest, except in queries whose places are all soft; which queries those are)."""
    if truth.ignored is None or not truth.ignored.any():
        return distances, np.zeros(len(distances), dtype=bool)
    all_soft = np.asarray(truth.ignored.all(axis=1), dtype=bool)
    return np.where(truth.ignored & ~all_soft[:, None], np.inf, distances).astype(distances.dtype), all_soft


def nearest_hits(distances: np.ndarray, correct: np.ndarray, depth: int) -> np.ndarray:
    """(N, depth) bool: whether a correct column is among each row's k + 1 nearest, k < depth.

    The nearest `depth` columns are found with np.argpartition and ordered by (distance, column),
    so ties at the top resolve to the lowest column like np.argmin; which tied columns enter at the
    depth boundary is unspecified."""
    n_database = distances.shape[1]
    if depth < n_database:
        nearest = np.argpartition(distances, depth - 1, axis=1)[:, :depth]
    else:
        nearest = np.broadcast_to(np.arange(n_database), distances.shape).copy()
    nearest_distances = np.take_along_axis(distances, nearest, axis=1)
    # lexsort keys: last is primary, so rows sort by distance, then by column index.
    rank = np.lexsort((nearest, nearest_distances), axis=1)
    nearest = np.take_along_axis(nearest, rank, axis=1)
    return np.logical_or.accumulate(np.take_along_axis(correct, nearest, axis=1), axis=1)


def block_records(distances: np.ndarray, truth: PairTruth, confidence: str, ratio_exclusion: int) -> QueryRecords:
    """The records of the query rows `truth` holds (a PairTruth.query_rows block) from their
    (rows, M) distances; confidence and ratio_exclusion go to distances.best_matches."""
    masked, all_soft = mask_soft(distances, truth)
    columns, scores = best_matches(masked, confidence, truth.database_places, ratio_exclusion)
    correct = truth.correct[np.arange(len(columns)), columns] & ~all_soft
    depth = min(max(RECALL_NS), distances.shape[1])
    # only a truth with soft cells can have all-soft queries, whose confidence needs it (final_confidence)
    largest = (
        -np.inf if truth.ignored is None else float(np.max(distances, where=np.isfinite(distances), initial=-np.inf))
    )
    matched = np.take_along_axis(masked, columns[:, None], axis=1)[:, 0].astype(np.float64)
    return QueryRecords(
        columns, matched, scores, correct, nearest_hits(masked, truth.correct, depth), all_soft, largest
    )


def final_confidence(records: QueryRecords, confidence: str) -> np.ndarray:
    """The confidences, all-soft queries at the lowest: as VPR_Tutorial (soft cells set to the
    lowest similarity), -(the largest finite distance of the pair) under "distance" (SeqSLAM's
    matrices hold +inf where no window fits), tied with the least confident other query under "ratio"."""
    if not records.all_soft.any():
        return records.confidence
    others = records.confidence[~records.all_soft]
    largest = records.largest_finite if np.isfinite(records.largest_finite) else 0.0
    lowest = -largest if confidence == "distance" else (others.min() if others.size else 0.0)
    return np.where(records.all_soft, lowest, records.confidence)
