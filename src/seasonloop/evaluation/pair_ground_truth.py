"""The ground truth of every season pair of a run, from its split and data.ground_truth, and the
record of it (metrics/ground_truth.json): which kind, what tolerance, how many queries have no
correct database place at all."""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from itertools import permutations
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.datasets import season_part, season_split
from seasonloop.data.ground_truth import PairTruth
from seasonloop.data.ground_truth_kinds import truth_kind
from seasonloop.params.seasons import pair_name
from seasonloop.params.settings import EvaluateConfig


def each_truth(
    kind: str,
    split: Mapping[str, Any],
    seasons: Sequence[str],
    evaluate: EvaluateConfig,
    frames_dir: Path,
    matrix_dir: Path,
) -> Iterator[tuple[tuple[str, str], PairTruth]]:
    """((database, query), its ground truth on the test places) for every ordered pair of seasons,
    one pair built at a time (a 27,592 x 27,592 pair's truth is 0.76 GB of booleans), as the kind
    data.ground_truth names builds it (seasonloop.data.ground_truth_kinds): positions read from
    frames_dir/<season>_positions.npy, matrices from matrix_dir."""
    truth = truth_kind(kind)
    test = {season: season_part(split, season, "test") for season in seasons}
    counts = {season: int(season_split(split, season)["n_places"]) for season in seasons}
    build = truth.pair_builder(seasons, test, counts, evaluate, frames_dir, matrix_dir)
    for database, query in permutations(seasons, 2):
        yield (database, query), build(database, query)


def pair_record(truth: PairTruth) -> dict[str, Any]:
    """One pair's entry of metrics/ground_truth.json: its queries, database places and queries
    without any correct database place."""
    return {
        "n_queries": len(truth.query_places),
        "n_database": len(truth.database_places),
        "n_without_match": truth.n_without_match,
        "mean_correct_per_query": float(np.mean(truth.correct.sum(axis=1))),
    }


def pooled_pair_record(per_fold: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """One pair's pair_record over the folds of a cross-validated run (each fold's queries matched
    against its own database places): every fold's queries, the largest fold's database (the most
    places a query is ranked against), and the mean correct places per query over all queries."""
    n_queries = sum(int(entry["n_queries"]) for entry in per_fold)
    return {
        "n_queries": n_queries,
        "n_database": max(int(entry["n_database"]) for entry in per_fold),
        "n_without_match": sum(int(entry["n_without_match"]) for entry in per_fold),
        "mean_correct_per_query": (
            sum(float(entry["mean_correct_per_query"]) * int(entry["n_queries"]) for entry in per_fold)
            / max(1, n_queries)
        ),
    }


def truth_record(
    kind: str, evaluate: EvaluateConfig, pairs: Mapping[tuple[str, str], dict[str, Any]]
) -> dict[str, Any]:
    """metrics/ground_truth.json: the kind, what is correct, and (database, query) -> pair_record."""
    return {
        "kind": kind,
        "correct": truth_kind(kind).describe(evaluate),
        "pairs": {pair_name(database, query): entry for (database, query), entry in pairs.items()},
    }
