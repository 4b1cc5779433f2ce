"""The test places and how to evaluate descriptors of them, as one object: what the stages that
evaluate a fitted learner outside the evaluate stage (the figures, the CAE width sweep, the
training-season ablation) build once and pass whole."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from seasonloop.data.ground_truth import PairTruth
from seasonloop.params.settings import EvaluateConfig, SequenceConfig, StatisticsConfig


@dataclass(frozen=True)
class EvaluationContext:
    """The test places and how to evaluate descriptors of them, built once by a stage and passed
    whole: the test images of each season (in the run's season order), the ground truth of each
    pair, the pairs to evaluate, the evaluate, sequence and statistics settings, and the batch size
    to describe in (the features stage's)."""

    test: Mapping[str, np.ndarray]
    truths: Mapping[tuple[str, str], PairTruth]
    pairs: Sequence[tuple[str, str]]
    evaluate: EvaluateConfig
    sequence: SequenceConfig
    statistics: StatisticsConfig
    batch_size: int
