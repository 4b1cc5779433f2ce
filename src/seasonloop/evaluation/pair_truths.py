"""The ground truth of every season pair of a run, from its split and data.ground_truth, and the
record of it (metrics/ground_truth.json): which kind, what tolerance, how many queries have no
correct database place at all."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from itertools import permutations
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.datasets import season_part, season_split
from seasonloop.data.truth_matrix import pair_matrix
from seasonloop.evaluation.ground_truth import PairTruth, aligned_truth, matrix_truth, position_truth
from seasonloop.io import load_array
from seasonloop.params.schema import GROUND_TRUTHS, pair_name
from seasonloop.params.settings import EvaluateConfig


def truth_file(folder: Path, database: str, query: str) -> Path:
    """Where the ground_truth stage writes the truth of (database, query)."""
    return Path(folder) / f"{pair_name(database, query)}.npz"


def each_truth(
    kind: str,
    split: Mapping[str, Any],
    seasons: Sequence[str],
    evaluate: EvaluateConfig,
    frames_dir: Path,
    matrix_dir: Path,
) -> Iterator[tuple[tuple[str, str], PairTruth]]:
    """((database, query), its ground truth on the test places) for every ordered pair of seasons,
    one pair built at a time (a 27,592 x 27,592 pair's truth is 0.76 GB of booleans).

    positions are read from frames_dir/<season>_positions.npy, matrices from
    matrix_dir/<database>-<query>.npz or its reverse, transposed, or VPR-Bench's
    matrix_dir/ground_truth_new.npy for (seasons[0], seasons[1]) = (reference, query)
    (seasonloop.data.truth_matrix)."""
    if kind not in GROUND_TRUTHS:
        raise ValueError(f"data.ground_truth: unknown kind '{kind}' (known: {', '.join(GROUND_TRUTHS)})")
    test = {season: season_part(split, season, "test") for season in seasons}
    build: Callable[[str, str], PairTruth]
    if kind == "aligned":

        def build(database: str, query: str) -> PairTruth:
            return aligned_truth(test[database], test[query], int(evaluate.tolerance_frames))

    elif kind == "positions":
        positions = {season: load_array(frames_dir / f"{season}_positions.npy") for season in seasons}

        def build(database: str, query: str) -> PairTruth:
            return position_truth(
                positions[database][test[database]],
                positions[query][test[query]],
                test[database],
                test[query],
                float(evaluate.tolerance_m),
            )

    else:
        counts = {season: int(season_split(split, season)["n_places"]) for season in seasons}
        vpr_bench = (seasons[0], seasons[1]) if kind == "vpr_bench" else None

        def build(database: str, query: str) -> PairTruth:
            needed_for = f"the evaluation of {query} queries against the {database} database needs it"
            hard, soft, path = pair_matrix(
                matrix_dir, database, query, counts[database], counts[query], needed_for, vpr_bench
            )
            return matrix_truth(hard, soft, test[database], test[query], str(path))

    for database, query in permutations(seasons, 2):
        yield (database, query), build(database, query)


def tolerance_text(kind: str, evaluate: EvaluateConfig) -> str:
    """What makes a match correct, in words, for the dataset table."""
    if kind == "aligned":
        return f"the query's own frame index +- {evaluate.tolerance_frames} places"
    if kind == "positions":
        return f"a database place within {float(evaluate.tolerance_m):g} m of the query's position"
    if kind == "vpr_bench":
        return "the reference places VPR-Bench's ground_truth_new.npy lists for the query"
    return "the ground-truth matrix given with the data ('hard'; 'soft' cells neither right nor wrong)"


def pair_record(truth: PairTruth) -> dict[str, Any]:
    """One pair's entry of metrics/ground_truth.json: its queries, database places and queries
    without any correct database place."""
    return {
        "n_queries": len(truth.query_places),
        "n_database": len(truth.database_places),
        "n_without_match": truth.n_without_match,
        "mean_correct_per_query": float(np.mean(truth.correct.sum(axis=1))),
    }


def truth_record(
    kind: str, evaluate: EvaluateConfig, pairs: Mapping[tuple[str, str], dict[str, Any]]
) -> dict[str, Any]:
    """metrics/ground_truth.json: the kind, what is correct, and (database, query) -> pair_record."""
    return {
        "kind": kind,
        "correct": tolerance_text(kind, evaluate),
        "pairs": {pair_name(database, query): entry for (database, query), entry in pairs.items()},
    }
