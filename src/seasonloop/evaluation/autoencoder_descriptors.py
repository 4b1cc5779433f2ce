"""What an auto-encoder's three descriptors (code, output, patch-normalised output) find: each
described from one forward pass, evaluated single-image on season pairs, with the fraction correct
and its interval along the route. The figures stage draws it (study Figure 19), the CAE width sweep
tabulates it (seasonloop.ablations.cae_widths)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from seasonloop.evaluation.blocks import PairEvaluation, evaluate_descriptors
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.models.core.autoencoder_learner import AE_DESCRIPTORS
from seasonloop.params.seasons import pair_name
from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import route_intervals


def autoencoder_descriptors(learner, context: EvaluationContext) -> dict[str, dict[str, np.ndarray]]:
    """described[descriptor][season] for the three auto-encoder descriptors.

    One forward pass gives the code and the output, and the patch-normalised output is derived
    from the output: the CAE costs ~9 GMAC per image.
    """
    described: dict[str, dict[str, np.ndarray]] = {descriptor: {} for descriptor in AE_DESCRIPTORS}
    for season, images in context.test.items():
        code, output = learner.describe_code_and_output(images, context.batch_size, progress=True)
        described["code"][season] = code
        described["output"][season] = output
        described["output_patchnorm"][season] = learner.patchnorm_output(output, images.shape[1:])
    return described


def descriptor_evaluations(
    described: Mapping[str, Mapping[str, np.ndarray]],
    context: EvaluationContext,
    descriptors: Sequence[str] = AE_DESCRIPTORS,
) -> dict[str, dict[str, PairEvaluation]]:
    """Single-image evaluation [descriptor][pair] of the context's pairs from described test images
    (described[descriptor][season], as autoencoder_descriptors gives them)."""
    return {
        descriptor: {
            pair_name(a, b): evaluate_descriptors(
                described[descriptor][a],
                described[descriptor][b],
                context.truths[(a, b)],
                "single",
                context.evaluate,
                context.sequence,
            )
            for a, b in context.pairs
        }
        for descriptor in descriptors
    }


def fraction_correct_record(evaluations: Mapping[str, PairEvaluation], statistics: StatisticsConfig) -> dict[str, Any]:
    """{fraction_correct: {pair: value}, interval: {pair: {low, high}}} of one descriptor's
    evaluations (pair -> PairEvaluation): the fraction correct with its 95% interval along
    the route (seasonloop.significance.intervals, the runs' persistence pooled over the pairs), as
    the evaluate stage draws it."""
    return {
        "fraction_correct": {pair: evaluation.metrics["fraction_correct"] for pair, evaluation in evaluations.items()},
        "interval": route_intervals(
            {pair: evaluation.outcomes.correct for pair, evaluation in evaluations.items()}, statistics
        ),
    }
