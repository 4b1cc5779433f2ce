"""Example matches and failures for the report: the most confident correct and wrong best
matches of one pair, read from the evaluate stage's per-query outcomes, drawn as image grids
(query, best match, true match).
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from seasonloop.data.ground_truth import PairTruth
from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.seasons import pair_name
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


def choose_examples(
    matches: np.ndarray, scores: np.ndarray, correct: np.ndarray, truth: PairTruth, n: int
) -> list[Example]:
    """The n most confident correct matches, then the n most confident failures (fewer if there are
    not n), from every query's best match (a column of the truth's database places), its confidence
    and correctness. The true match is the truth's exact match of the query (its best match when it
    has none). Ties in confidence keep query order, so the choice is deterministic."""
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


def outcome_examples(outcomes: QueryOutcomes, truth: PairTruth, n: int) -> list[Example]:
    """choose_examples from an evaluation's per-query outcomes (seasonloop.evaluation.outcomes),
    which keep each query's best match: the evaluate stage's own matches, not a second matching.
    Outcomes of every fold of a cross-validated run give the truth's (one fold's) queries' rows."""
    row = {int(place): i for i, place in enumerate(outcomes.query_place)}
    if not all(int(place) in row for place in truth.query_places):
        raise ValueError("per-query outcomes and ground truth hold different queries (rerun the evaluate stage)")
    outcomes = outcomes.take(np.array([row[int(place)] for place in truth.query_places], dtype=np.int64))
    column = {int(place): i for i, place in enumerate(truth.database_places)}
    if not all(int(place) in column for place in outcomes.match_place):
        raise ValueError(
            "per-query outcomes match places outside the ground truth's database (rerun the evaluate stage)"
        )
    matches = np.array([column[int(place)] for place in outcomes.match_place], dtype=np.int64)
    return choose_examples(matches, outcomes.confidence, outcomes.correct, truth, n)


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
    outcomes_dir: Path,
    learners: Sequence[str],
    database: str,
    query: str,
    images: Mapping[str, np.ndarray],
    truth: PairTruth,
    n: int,
) -> dict[str, bytes]:
    """learner -> PNG bytes of its example grid on the pair (database, query): its single-image best
    matches under evaluate.metric as the evaluate stage found them (outcomes_dir/<learner>/<pair>.csv),
    the n most confident correct ones and n most confident failures, by the pair's ground truth."""
    grids = {}
    for learner in learners:
        outcomes = QueryOutcomes.read_csv(outcomes_dir / learner / f"{pair_name(database, query)}.csv")
        grids[learner] = example_grid_png(
            images[database],
            images[query],
            outcome_examples(outcomes, truth, n),
            truth.database_places,
            truth.query_places,
            title=f"{learner}: {query} queries vs {database} database",
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
            *(Image(f"{learner}, {pair}", png) for learner, png in grids.items()),
        ],
    )
