"""The paired comparisons of a run from the evaluate stages' per-query outcomes: the files read
here, the statistics in seasonloop.significance.tables."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.tables import Variant, comparison_tables, pair_comparisons


def run_comparisons(
    outcomes_dir: Path,
    methods: Sequence[str],
    variants: Sequence[Variant],
    pairs: Sequence[str],
    settings: StatisticsConfig,
) -> dict[str, Any]:
    """Every table of every season pair from outcomes_dir/<method>/<pair><suffix>.csv, with the
    settings they were computed under."""
    tables = comparison_tables(methods, variants)
    source = {method + suffix: (method, suffix) for method in methods for _, _, suffix in variants}

    def reader(pair: str) -> Callable[[str], tuple[np.ndarray, np.ndarray]]:
        def outcome_of(label: str) -> tuple[np.ndarray, np.ndarray]:
            method, suffix = source[label]
            outcomes = QueryOutcomes.read_csv(outcomes_dir / method / f"{pair}{suffix}.csv")
            return outcomes.query_place, outcomes.correct

        return outcome_of

    return {
        "statistics": asdict(settings),
        "pairs": {pair: pair_comparisons(reader(pair), tables, settings) for pair in pairs},
    }
