"""Each query's outcome of one evaluation (one learner, pair, metric and matcher): what the
statistics of seasonloop.significance are computed from, saved beside the metrics so that intervals
and paired tests need no second evaluation.

A CSV, one row per query in the pair's query order (route order: consecutive rows are neighbouring
test places): query_place, correct (its best match is right), confidence (higher = more confident,
as the PR curve ranks it), has_match (some database place is correct: recall@N counts only these),
hit_at_1 (its nearest database place is correct: recall@1's numerator), match_place (the database
place of its best match) and match_distance (the distance matched on there), so that the report
shows example matches without matching again.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from seasonloop.data.ground_truth import PairTruth
from seasonloop.evaluation.records import QueryRecords, final_confidence

COLUMNS = ("query_place", "correct", "confidence", "has_match", "hit_at_1", "match_place", "match_distance")


@dataclass(frozen=True)
class QueryOutcomes:
    """Per query of one evaluation, in query order (the columns of the module's CSV)."""

    query_place: np.ndarray  # (n,) int64
    correct: np.ndarray  # (n,) bool
    confidence: np.ndarray  # (n,) float64
    has_match: np.ndarray  # (n,) bool
    hit_at_1: np.ndarray  # (n,) bool
    match_place: np.ndarray  # (n,) int64: the database place of the best match
    match_distance: np.ndarray  # (n,) float64

    @classmethod
    def from_records(cls, records: QueryRecords, truth: PairTruth, confidence: str) -> QueryOutcomes:
        """The outcomes of a pair's records (every block in) under its truth; `confidence` is
        evaluate.confidence (all-soft queries get the pair's lowest, records.final_confidence)."""
        return cls(
            np.asarray(truth.query_places, np.int64),
            np.asarray(records.correct, bool),
            np.asarray(final_confidence(records, confidence), np.float64),
            np.asarray(truth.has_match, bool),
            np.asarray(records.hit_within[:, 0], bool) & np.asarray(truth.has_match, bool),
            np.asarray(truth.database_places, np.int64)[records.best],
            np.asarray(records.distance, np.float64),
        )

    def take(self, rows: np.ndarray) -> QueryOutcomes:
        """The outcomes of the queries at `rows`, in that order."""
        return QueryOutcomes(**{name: getattr(self, name)[rows] for name in COLUMNS})

    def to_csv(self, path: Path) -> None:
        table = pd.DataFrame({name: getattr(self, name) for name in COLUMNS})
        for name in ("correct", "has_match", "hit_at_1"):
            table[name] = table[name].astype(np.int8)
        table.to_csv(path, index=False, float_format="%.9g")

    @classmethod
    def read_csv(cls, path: Path) -> QueryOutcomes:
        """The outcomes a to_csv wrote, or a one-line error naming the file."""
        try:
            table = pd.read_csv(path)
        except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as error:
            raise ValueError(f"{path}: cannot read per-query outcomes ({error})") from None
        missing = [name for name in COLUMNS if name not in table.columns]
        if missing:
            raise ValueError(
                f"{path}: per-query outcomes lack column(s) {', '.join(missing)} (rerun the evaluate stage)"
            )
        return cls(
            table["query_place"].to_numpy(np.int64),
            table["correct"].to_numpy().astype(bool),
            table["confidence"].to_numpy(np.float64),
            table["has_match"].to_numpy().astype(bool),
            table["hit_at_1"].to_numpy().astype(bool),
            table["match_place"].to_numpy(np.int64),
            table["match_distance"].to_numpy(np.float64),
        )
