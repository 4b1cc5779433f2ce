"""One pair's evaluation over the folds of a cross-validated run (split.folds K > 1,
seasonloop.data.split.fold_blocks): each fold's queries were matched against that fold's own test
places of the database season by the learner fitted without them, as in the study's split; the
pair's result is every fold's queries at once, in route order.

The metrics and PR curve are those of all queries, their confidences ranked together (each scored
by its own fold's model: the PR-based metrics compare the distances of K fits, fraction correct and
recall@N do not); the outcomes, in route order, are what the intervals and paired tests
read, so a verdict rests on every tested place. The similarity thumbnail is the last fold's (the
study's split): a picture of one matrix, not of K.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from seasonloop.evaluation.blocks import PairEvaluation
from seasonloop.evaluation.metrics import summarise_queries
from seasonloop.evaluation.outcomes import COLUMNS, QueryOutcomes
from seasonloop.evaluation.records import QueryRecords, final_confidence


def pooled_evaluation(folds: Sequence[PairEvaluation], confidence: str) -> PairEvaluation:
    """The evaluation of every fold's queries (folds: one pair and matcher, fold 0 first); its
    "n_database" is the largest fold's (the most places a query was ranked against), "folds" says
    how many. `confidence` is evaluate.confidence."""
    if len(folds) == 1:
        return folds[0]
    places = np.concatenate([fold.outcomes.query_place for fold in folds])
    order = np.argsort(places, kind="stable")  # route order: the folds' blocks interleave
    if len(np.unique(places)) != len(places):
        raise ValueError("folds: a query place is tested by two folds (rerun the split stage)")
    depth = max(fold.records.hit_within.shape[1] for fold in folds)
    records = QueryRecords.concatenate([_deepened(fold.records, depth) for fold in folds])
    records = replace(records, **{name: getattr(records, name)[order] for name in QueryRecords._ARRAYS})
    pooled = {name: np.concatenate([getattr(fold.outcomes, name) for fold in folds]) for name in COLUMNS}
    # all-soft queries at the lowest confidence of every fold's, as the pooled PR curve ranks them
    outcomes = replace(QueryOutcomes(**pooled).take(order), confidence=final_confidence(records, confidence))
    largest = max(int(fold.metrics["n_database"]) for fold in folds)
    metrics, pr = summarise_queries(records, outcomes.has_match, largest, confidence)
    metrics["folds"] = len(folds)
    return PairEvaluation(metrics, pr, folds[-1].thumbnail, outcomes, records)


def _deepened(records: QueryRecords, depth: int) -> QueryRecords:
    """records whose hit_within holds `depth` columns: a fold with fewer database places than the
    deepest recall@N has found all it can, so its last column repeats."""
    hits = records.hit_within
    extra = np.repeat(hits[:, -1:], depth - hits.shape[1], axis=1)
    return replace(records, hit_within=np.concatenate([hits, extra], axis=1))
