"""A pair evaluated a block of query rows at a time: only (rows, M) distances are held at once (a
27,592 x 27,592 pair's float32 distances are 3 GB), with the numbers of the whole matrix
(matchers.match_distances): the matchers' blocks, the per-query records of each block
(seasonloop.evaluation.records) summarised once every block is in, and the similarity thumbnail
built from whole groups of rows.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.data.ground_truth import PairTruth
from seasonloop.evaluation.distances import distance_matrix
from seasonloop.evaluation.matchers import get_matcher, row_blocks
from seasonloop.evaluation.metrics import summarise_records
from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.evaluation.records import QueryRecords, block_records
from seasonloop.params.settings import EvaluateConfig, SequenceConfig

# the thumbnails' largest side: a figure of every learner and pair shows each in ~200 px
THUMBNAIL_SIDE = 160
# query rows evaluated at once: (rows, M) float32 distances, 0.23 GB a copy at Nordland's 27,592
# database places (the default run's pairs are one block, the full run's 3,259 queries two)
EVALUATION_ROWS_PER_BLOCK = 2048
# a pair's float32 distances up to this size are computed once, whole, for all its matchers
# (the full run's 3,259 x 3,259: 42 MB); larger ones block by block (27,592 x 27,592: 3 GB)
WHOLE_DISTANCES_MAX_BYTES = 512 * 2**20


@dataclass(frozen=True)
class PairEvaluation:
    """One pair evaluated with one matcher: its metrics (seasonloop.evaluation.metrics.METRIC_KEYS),
    PR curve, similarity thumbnail, each query's outcome (what intervals and paired tests use) and
    the records its metrics summarise (what pools the folds of a cross-validated run)."""

    metrics: dict[str, Any]
    pr: pd.DataFrame
    thumbnail: np.ndarray
    outcomes: QueryOutcomes
    records: QueryRecords


def similarity_thumbnail(distances: np.ndarray, max_side: int = THUMBNAIL_SIDE) -> np.ndarray:
    """float16 similarity in [0, 1] (1: the pair's smallest distance, 0: its largest finite one; NaN
    where the distance is infinite), downsampled to at most max_side a side by the minimum distance
    over blocks, so the low-distance line of true matches stays visible. Scaled per matrix: learners
    measure distance in their own units, and a picture compares where the matches lie, not units."""
    groups = [thumbnail_group(size, max_side) for size in np.shape(distances)]
    return scale_thumbnail(thumbnail_minima(distances, *groups))


def thumbnail_group(size: int, max_side: int = THUMBNAIL_SIDE) -> int:
    """Rows (columns) of a matrix side of `size` that one thumbnail pixel takes the minimum of."""
    return int(np.ceil(size / max_side)) if size > max_side else 1


def thumbnail_minima(distances: np.ndarray, row_group: int, column_group: int) -> np.ndarray:
    """The minimum distance of each row_group x column_group block (float64); a block of rows that
    starts at a multiple of row_group gives the thumbnail's rows of those rows."""
    distances = np.asarray(distances, dtype=np.float64)
    for axis, group in ((0, row_group), (1, column_group)):
        if group > 1:
            distances = np.minimum.reduceat(distances, np.arange(0, distances.shape[axis], group), axis=axis)
    return distances


def scale_thumbnail(minima: np.ndarray) -> np.ndarray:
    """similarity_thumbnail's scaling of the whole pair's thumbnail_minima."""
    finite = np.isfinite(minima)
    if not finite.any():
        return np.full(minima.shape, np.nan, dtype=np.float16)
    low, high = minima[finite].min(), minima[finite].max()
    scaled = (high - minima) / (high - low) if high > low else np.ones_like(minima)
    return np.where(finite, scaled, np.nan).astype(np.float16)


def evaluate_in_blocks(
    distance_rows: Callable[[slice], np.ndarray],
    n_database: int,
    truth: PairTruth,
    matcher: str,
    evaluate: EvaluateConfig,
    sequence: SequenceConfig,
    rows_per_block: int = EVALUATION_ROWS_PER_BLOCK,
) -> PairEvaluation:
    """One pair with one matcher (metrics, PR curve, similarity thumbnail, outcomes), a block of query rows
    at a time: only (rows_per_block, M) distances are held at once, and the numbers are those of
    the whole matrix (matchers.match_distances). distance_rows(rows): the descriptor distances of
    query rows `rows` to the whole database."""
    n_queries = len(truth.query_places)
    row_group = thumbnail_group(n_queries)
    rows_per_block = max(row_group, rows_per_block // row_group * row_group)  # thumbnail rows whole
    blocks = get_matcher(matcher).blocks(
        distance_rows, n_queries, n_database, rows_per_block, truth.database_places, truth.query_places, sequence
    )
    records, minima = [], []
    for rows, matched in blocks:
        records.append(
            block_records(matched, truth.query_rows(rows), evaluate.confidence, int(evaluate.ratio_exclusion))
        )
        minima.append(thumbnail_minima(matched, row_group, thumbnail_group(n_database)))
    pair_records = QueryRecords.concatenate(records)
    metrics, pr = summarise_records(pair_records, truth, evaluate.confidence)
    outcomes = QueryOutcomes.from_records(pair_records, truth, evaluate.confidence)
    return PairEvaluation(metrics, pr, scale_thumbnail(np.concatenate(minima)), outcomes, pair_records)


def evaluate_descriptors(
    database: np.ndarray,
    queries: np.ndarray,
    truth: PairTruth,
    matcher: str,
    evaluate: EvaluateConfig,
    sequence: SequenceConfig,
    metric: str | None = None,
) -> PairEvaluation:
    """One pair's descriptors evaluated under `metric` (default evaluate.metric) with one matcher, in blocks of query rows (evaluate_in_blocks)."""
    distance_rows = matched_distances(
        database, queries, truth, matcher, evaluate.metric if metric is None else metric, sequence
    )
    return evaluate_in_blocks(distance_rows, len(database), truth, matcher, evaluate, sequence)


def matched_distances(
    database: np.ndarray, queries: np.ndarray, truth: PairTruth, matcher: str, metric: str, sequence: SequenceConfig
) -> Callable[[slice], np.ndarray]:
    """pair_distances between the descriptors `matcher` takes (Matcher.described: each traverse's
    own, or its sequence descriptors over the truth's place ids)."""
    taken = get_matcher(matcher)
    return pair_distances(
        taken.described(database, truth.database_places, sequence),
        taken.described(queries, truth.query_places, sequence),
        metric,
    )


def pair_distances(
    database: np.ndarray, queries: np.ndarray, metric: str, whole_max_bytes: int = WHOLE_DISTANCES_MAX_BYTES
) -> Callable[[slice], np.ndarray]:
    """Query rows -> their distances to the database: a pair whose float32 distances fit in
    whole_max_bytes is computed once, whole, and shared by its matchers (every pair of the default
    and full runs: the values a whole distance_matrix gives); a larger one is computed for the rows
    asked, never whole."""
    if len(queries) * len(database) * 4 <= whole_max_bytes:
        distances = distance_matrix(database, queries, metric=metric)
        return lambda rows: distances[rows]
    return lambda rows: distance_matrix(database, queries[rows], metric=metric)


def best_columns(
    database: np.ndarray, queries: np.ndarray, metric: str, rows_per_block: int = EVALUATION_ROWS_PER_BLOCK
) -> np.ndarray:
    """Each query's best database column (np.argmin: ties to the lowest), a block of rows at a time."""
    distance_rows = pair_distances(database, queries, metric)
    return np.concatenate([np.argmin(distance_rows(rows), axis=1) for rows in row_blocks(len(queries), rows_per_block)])
