"""The pipeline's ground truth, for the stages that evaluate: binds the ground_truth stage's folder
to seasonloop.data.ground_truth (kept apart from _datasets.py so that the stages which fit
and describe do not depend on evaluation code)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from itertools import permutations
from pathlib import Path
from typing import Any

import numpy as np

import _common  # noqa: F401  (this checkout's library first: see _common.py)
from seasonloop.data.ground_truth import PairTruth, truth_file
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.params.settings import EvaluateConfig, FeaturesConfig, SequenceConfig, StatisticsConfig

TRUTHS = Path("data/ground_truth")


def pair_truths(pairs: Iterable[tuple[str, str]]) -> dict[tuple[str, str], PairTruth]:
    """(database, query) -> its ground truth on the test places (the ground_truth stage's)."""
    return {pair: PairTruth.load(truth_file(TRUTHS, *pair)) for pair in pairs}


class TruthFiles(Mapping[tuple[str, str], PairTruth]):
    """(database, query) -> its ground truth, read from its file at each access: a 27,592 x 27,592
    pair's is 0.76 GB of booleans, so a stage that looks at every pair holds one at a time."""

    def __init__(self, pairs: Iterable[tuple[str, str]]) -> None:
        self._pairs = list(pairs)

    def __getitem__(self, pair: tuple[str, str]) -> PairTruth:
        if pair not in self._pairs:
            raise KeyError(pair)
        return PairTruth.load(truth_file(TRUTHS, *pair))

    def __iter__(self) -> Iterator[tuple[str, str]]:
        return iter(self._pairs)

    def __len__(self) -> int:
        return len(self._pairs)


def all_pair_truths(seasons: list[str]) -> Mapping[tuple[str, str], PairTruth]:
    """The ground truth of every ordered pair of `seasons`, each read when asked for (TruthFiles)."""
    return TruthFiles(permutations(seasons, 2))


def evaluation_context(
    params: dict[str, Any],
    test: Mapping[str, np.ndarray],
    truths: Mapping[tuple[str, str], PairTruth],
    pairs: Sequence[tuple[str, str]],
) -> EvaluationContext:
    """The test images `test`, the truths and the pairs to evaluate, with the run's evaluate,
    sequence and statistics settings and the features stage's batch size."""
    return EvaluationContext(
        test,
        truths,
        pairs,
        EvaluateConfig.from_params(params),
        SequenceConfig.from_params(params),
        StatisticsConfig.from_params(params),
        FeaturesConfig.from_params(params).batch_size,
    )
