"""Example matches and failures for the report: the most confident correct and wrong best
matches of one pair, drawn as image grids (query, best match, true match).
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from seasonloop.data.ground_truth import PairTruth
from seasonloop.evaluation.blocks import EVALUATION_ROWS_PER_BLOCK, pair_distances
from seasonloop.evaluation.matchers import row_blocks
from seasonloop.evaluation.metrics import truth_matches
from seasonloop.evaluation.records import QueryRecords, block_records, final_confidence
from seasonloop.io import load_array
from seasonloop.params.settings import EvaluateConfig
from seasonloop.plots import plot_image_grid
from seasonloop.reporting.html import Image, Png, Section, Text


@dataclass(frozen=True)
class Example:
    """One query's best match: indices into the query and database sets."""

    query: int
    match: int
    truth: int
    correct: bool
    confidence: float


def select_examples(
    distances: np.ndarray, truth: PairTruth, confidence: str, n: int, ratio_exclusion: int = 0
) -> list[Example]:
    """The n most confident correct matches, then the n most confident failures (fewer if there are not n).

    distances is (queries, database); the true match is the truth's exact match of the query (the
    query's own column when it has none). Ties in confidence keep query order, so the choice is
    deterministic.
    """
    database_places, query_places = truth.database_places, truth.query_places
    if np.shape(distances) != (len(query_places), len(database_places)):
        raise ValueError(
            f"distances shape {np.shape(distances)} does not match "
            f"(queries, database) = ({len(query_places)}, {len(database_places)})"
        )
    return choose_examples(*truth_matches(np.asarray(distances), truth, confidence, ratio_exclusion), truth, n)


def blocked_examples(
    distance_rows: Callable[[slice], np.ndarray],
    n_database: int,
    truth: PairTruth,
    confidence: str,
    n: int,
    ratio_exclusion: int = 0,
) -> list[Example]:
    """select_examples a block of query rows at a time (a 27,592 x 27,592 pair's distances are 3 GB):
    distance_rows(rows) gives the distances of query rows `rows`."""
    records = QueryRecords.concatenate(
        [
            block_records(distance_rows(rows), truth.query_rows(rows), confidence, ratio_exclusion)
            for rows in row_blocks(len(truth.query_places), EVALUATION_ROWS_PER_BLOCK)
        ]
    )
    return choose_examples(records.best, final_confidence(records, confidence), records.correct, truth, n)


def choose_examples(
    matches: np.ndarray, scores: np.ndarray, correct: np.ndarray, truth: PairTruth, n: int
) -> list[Example]:
    """select_examples' choice from every query's best match, its confidence and correctness."""
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    order = np.argsort(-scores, kind="stable")
    chosen = [*order[correct[order]][:n], *order[~correct[order]][:n]]
    return [
        Example(
            query=int(q),
            match=int(matches[q]),
            truth=int(truth.exact[q]) if truth.exact[q] >= 0 else int(matches[q]),
            correct=bool(correct[q]),
            confidence=float(scores[q]),
        )
        for q in chosen
    ]


def example_grid_png(
    database_images: np.ndarray,
    query_images: np.ndarray,
    examples: Sequence[Example],
    database_places: np.ndarray,
    query_places: np.ndarray,
    title: str,
) -> bytes:
    """PNG bytes of a grid, one row per example: query image, best match, true match."""
    if not examples:
        raise ValueError("examples is empty: nothing to plot")
    rows = [[query_images[e.query], database_images[e.match], database_images[e.truth]] for e in examples]
    # short lines: the labels are drawn vertically beside images only a few lines tall
    labels = [
        f"correct\nplace {query_places[e.query]}"
        if e.correct
        else f"wrong\nplace {query_places[e.query]}\nmatched {database_places[e.match]}"
        for e in examples
    ]
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "examples.png"
        plot_image_grid(rows, path, row_labels=labels, col_labels=["query", "best match", "true match"], title=title)
        return path.read_bytes()


def example_grids(
    features_dir: Path,
    methods: Sequence[str],
    database: str,
    query: str,
    images: Mapping[str, np.ndarray],
    truth: PairTruth,
    evaluate: EvaluateConfig,
    n: int,
) -> dict[str, bytes]:
    """method -> PNG bytes of its example grid on the pair (database, query): single-image best
    matches of the descriptors features_dir/<method>/<season>.npy under evaluate.metric, the n
    most confident correct ones and n most confident failures, by the pair's ground truth."""
    grids = {}
    for method in methods:
        features = features_dir / method
        database_descriptors = load_array(features / f"{database}.npy")
        distance_rows = pair_distances(database_descriptors, load_array(features / f"{query}.npy"), evaluate.metric)
        examples = blocked_examples(
            distance_rows, len(database_descriptors), truth, evaluate.confidence, n, int(evaluate.ratio_exclusion)
        )
        grids[method] = example_grid_png(
            images[database],
            images[query],
            examples,
            truth.database_places,
            truth.query_places,
            title=f"{method}: {query} queries vs {database} database",
        )
    return grids


def examples_section(pair: str, grids: Mapping[str, Png]) -> Section:
    """The example grids of one pair, learner -> PNG."""
    return Section(
        f"Example matches and failures, {pair}",
        [
            Text(
                "Single-image matching. Per learner: the most confident correct matches, then the most "
                "confident wrong ones (query, its best database match, the true database image)."
            ),
            *(Image(f"{method}, {pair}", png) for method, png in grids.items()),
        ],
    )
