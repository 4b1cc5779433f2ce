"""One evaluation of a season pair: distances, the matcher, metrics and PR curve.

A learner is evaluated once per (metric, matcher): the metric `evaluate.metric` and every metric
of `evaluate.extra_metrics`, each with every matcher of `evaluate.matchers`. Results carry a
suffix in file names and table labels: "@<metric>" for an extra metric (none for the main one),
then the matcher's ("+seq" for sequence matching), e.g. "pca", "pca+seq", "pca@cityblock+seq".

MATCHER_REGISTRY holds the matchers: name -> the suffix its results carry, what it makes of each
traverse's descriptors before distances are taken (sequence descriptors: delta, smoothed; nothing
for single and sequence), and the function that turns those distances into the distances matched
on, a block of query rows at a time (SeqSLAM's sequence scores; the distances themselves
otherwise). MATCHERS is its name -> suffix view. The params are checked once, by the sections'
checks (seasonloop.params.settings) when EvaluateConfig / SequenceConfig are built: this module
only computes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from seasonloop.data.ground_truth import PairTruth
from seasonloop.evaluation.descriptor_sequences import delta_descriptors, smoothed_descriptors
from seasonloop.evaluation.metrics import evaluate_truth
from seasonloop.evaluation.sequence import sequence_distance_blocks
from seasonloop.params.settings import EvaluateConfig, SequenceConfig

if TYPE_CHECKING:
    import pandas as pd

# The distances a matcher matches on, a block of query rows at a time: (distance_rows (query rows ->
# their (rows, M) descriptor distances), N, M, rows per block, database_places (M,), query_places
# (N,), sequence) -> (rows, their (rows, M) distances to match on) for consecutive blocks of rows.
MatchBlocks = Callable[
    [Callable[[slice], np.ndarray], int, int, int, np.ndarray, np.ndarray, SequenceConfig],
    Iterator[tuple[slice, np.ndarray]],
]


# What a matcher makes of one traverse's descriptors before distances are taken: (descriptors (n, d),
# their place ids (n,), sequence) -> descriptors (n, d')
Describe = Callable[[np.ndarray, np.ndarray, SequenceConfig], np.ndarray]


@dataclass(frozen=True)
class Matcher:
    """One value of evaluate.matchers: the suffix its results carry, what tables and figures call
    it, what it matches on, and what it makes of the descriptors first (None: they are matched as
    they are)."""

    suffix: str
    title: str
    blocks: MatchBlocks
    describe: Describe | None = None

    def described(self, descriptors: np.ndarray, places: np.ndarray, sequence: SequenceConfig) -> np.ndarray:
        """The descriptors this matcher takes distances between."""
        return descriptors if self.describe is None else self.describe(descriptors, places, sequence)


def row_blocks(n_rows: int, rows_per_block: int) -> list[slice]:
    """Consecutive blocks of at most rows_per_block of n_rows rows."""
    return [slice(start, min(start + rows_per_block, n_rows)) for start in range(0, n_rows, rows_per_block)]


def _single_image(
    distance_rows: Callable[[slice], np.ndarray],
    n_queries: int,
    n_database: int,
    rows_per_block: int,
    database_places: np.ndarray,
    query_places: np.ndarray,
    sequence: SequenceConfig,
) -> Iterator[tuple[slice, np.ndarray]]:
    for rows in row_blocks(n_queries, rows_per_block):
        yield rows, distance_rows(rows)


def _sequence(
    distance_rows: Callable[[slice], np.ndarray],
    n_queries: int,
    n_database: int,
    rows_per_block: int,
    database_places: np.ndarray,
    query_places: np.ndarray,
    sequence: SequenceConfig,
) -> Iterator[tuple[slice, np.ndarray]]:
    # Sequence matching restarts at every break in the place ids (seasonloop.evaluation.sequence).
    return sequence_distance_blocks(
        distance_rows, n_queries, n_database, rows_per_block, sequence, query_places, database_places
    )


def _delta(descriptors: np.ndarray, places: np.ndarray, sequence: SequenceConfig) -> np.ndarray:
    return delta_descriptors(descriptors, places, int(sequence.length), sequence.descriptor_window_at_breaks)


def _smoothed(descriptors: np.ndarray, places: np.ndarray, sequence: SequenceConfig) -> np.ndarray:
    return smoothed_descriptors(descriptors, places, int(sequence.length), sequence.descriptor_window_at_breaks)


# A new matcher is one function plus one line here (evaluate.matchers is checked against it). The
# sequence descriptors take SeqSLAM's sequence.length frames: every sequence matcher sees as many.
MATCHER_REGISTRY: dict[str, Matcher] = {
    "single": Matcher("", "single-image matching", _single_image),
    "sequence": Matcher("+seq", "sequence matching (SeqSLAM)", _sequence),
    "delta": Matcher("+delta", "Delta descriptors (Garg et al. 2020)", _single_image, _delta),
    "smoothed": Matcher("+smoothed", "smoothed descriptors (the window's mean)", _single_image, _smoothed),
}
# matcher -> the suffix its results carry in file names and tables ("pca" vs "pca+seq")
MATCHERS: dict[str, str] = {name: matcher.suffix for name, matcher in MATCHER_REGISTRY.items()}
# a result suffix -> what its matcher is called ("+seq": "sequence matching (SeqSLAM)")
MATCHER_TITLES: dict[str, str] = {matcher.suffix: matcher.title for matcher in MATCHER_REGISTRY.values()}


def get_matcher(name: str) -> Matcher:
    """The matcher registered under `name`."""
    if name not in MATCHER_REGISTRY:
        raise ValueError(f"evaluate.matchers: unknown matcher '{name}' (known: {', '.join(MATCHER_REGISTRY)})")
    return MATCHER_REGISTRY[name]


def result_suffix(metric: str, matcher: str, evaluate: EvaluateConfig) -> str:
    """The suffix of one evaluation's results: '@<metric>' for an extra metric, then the matcher's."""
    return ("" if metric == evaluate.metric else f"@{metric}") + get_matcher(matcher).suffix


def evaluations(evaluate: EvaluateConfig) -> list[tuple[str, str, str]]:
    """(metric, matcher, suffix) of every evaluation of a learner on a pair, in table order: the
    main metric's matchers first, then each extra metric's."""
    return [
        (metric, matcher, result_suffix(metric, matcher, evaluate))
        for metric in [evaluate.metric, *evaluate.extra_metrics]
        for matcher in evaluate.matchers
    ]


def match_distances(
    distances: np.ndarray, truth: PairTruth, matcher: str, evaluate: EvaluateConfig, sequence: SequenceConfig
) -> tuple[dict[str, Any], pd.DataFrame, np.ndarray]:
    """(metrics, PR curve, distance matrix used for matching) from one pair's descriptor distances
    (between the descriptors the matcher takes: Matcher.described) and its ground truth (whose place ids tell the sequence matcher where the route breaks), the
    whole matrix as one block (blocks.evaluate_in_blocks: a large pair in blocks).

    evaluate gives the confidence and ratio exclusion; sequence the sequence matcher's settings.
    """
    n_queries, n_database = np.shape(distances)
    [(_, matched)] = get_matcher(matcher).blocks(
        lambda rows: distances[rows],
        n_queries,
        n_database,
        max(1, n_queries),
        truth.database_places,
        truth.query_places,
        sequence,
    )
    metrics, pr = evaluate_truth(
        matched, truth, confidence=evaluate.confidence, ratio_exclusion=int(evaluate.ratio_exclusion)
    )
    return metrics, pr, matched
