"""The pipeline's ground truth, for the stages that evaluate: binds the ground_truth stage's folder
to seasonloop.evaluation.ground_truth (kept apart from _datasets.py so that the stages which fit
and describe do not depend on evaluation code)."""

from __future__ import annotations

from collections.abc import Iterable
from itertools import permutations
from pathlib import Path

from seasonloop.evaluation.ground_truth import PairTruth
from seasonloop.evaluation.pair_truths import truth_file

TRUTHS = Path("data/ground_truth")


def pair_truths(pairs: Iterable[tuple[str, str]]) -> dict[tuple[str, str], PairTruth]:
    """(database, query) -> its ground truth on the test places (the ground_truth stage's)."""
    return {pair: PairTruth.load(truth_file(TRUTHS, *pair)) for pair in pairs}


def all_pair_truths(seasons: list[str]) -> dict[tuple[str, str], PairTruth]:
    """The ground truth of every ordered pair of `seasons`."""
    return pair_truths(permutations(seasons, 2))
