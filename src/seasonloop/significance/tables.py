"""The paired comparisons of a run, table by table: which evaluations are compared on each season
pair, and the comparisons themselves from the evaluations' per-query outcomes.

A table is a family of comparisons whose p-values are Holm-corrected together
(seasonloop.significance.paired.with_verdicts), on one season pair:
- "learners<suffix>": every two learners under one evaluation (suffix "" = evaluate.metric, single
  images; "+seq"; "@cityblock"; ...), the first in `learners` order first;
- "matchers<suffix>": each learner's matcher against its single-image matching under one metric
  ("matchers+seq", "matchers@cityblock+seq"), and "matchers<suffix> vs <other>" against each
  matcher before it in evaluate.matchers ("matchers+delta vs +seq": Delta descriptors against
  SeqSLAM);
- "distances<suffix>": each learner under an extra metric against evaluate.metric, one matcher
  ("distances@cityblock", "distances@cityblock+seq").
Labels are <learner><suffix>, as everywhere (seasonloop.evaluation.matchers.result_suffix).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from itertools import combinations
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import persistence, routes_of
from seasonloop.significance.paired import differences, paired_difference, with_verdicts

Variant = tuple[str, str, str]  # (metric, matcher, suffix): seasonloop.evaluation.matchers.evaluations


def comparison_tables(learners: Sequence[str], variants: Sequence[Variant]) -> dict[str, list[tuple[str, str]]]:
    """table name -> the (first, second) labels it compares; variants in evaluations' order (the
    main metric's first, single images before sequences). A variant is compared with its reference
    (the same metric's first matcher; the same matcher under the main metric) in table
    "matchers<its suffix>" ("matchers+seq", "matchers@cityblock+seq") or "distances<its suffix>",
    and with every matcher before it under its metric in "matchers<its suffix> vs <that matcher's
    suffix>" ("matchers+delta vs +seq")."""
    suffix = {(metric, matcher): suffix for metric, matcher, suffix in variants}
    main_metric, first_matcher = variants[0][0], variants[0][1]
    tables: dict[str, list[tuple[str, str]]] = {}
    for _, _, variant_suffix in variants:
        tables[f"learners{variant_suffix}"] = list(combinations([learner + variant_suffix for learner in learners], 2))
    for (metric, matcher), variant_suffix in suffix.items():
        metric_part = "" if metric == main_metric else f"@{metric}"
        earlier = [other for (other_metric, other), _ in suffix.items() if other_metric == metric]
        for other in earlier[: earlier.index(matcher)]:
            reference = suffix[(metric, other)]
            name = f"matchers{variant_suffix}" + (
                "" if other == first_matcher else f" vs {reference[len(metric_part) :]}"
            )
            tables[name] = [(learner + variant_suffix, learner + reference) for learner in learners]
    for (metric, matcher), variant_suffix in suffix.items():
        if metric != main_metric and (main_metric, matcher) in suffix:
            reference = suffix[(main_metric, matcher)]
            tables[f"distances{variant_suffix}"] = [
                (learner + variant_suffix, learner + reference) for learner in learners
            ]
    return tables


def pair_comparisons(
    outcome_of: Callable[[str], tuple[np.ndarray, np.ndarray]],
    tables: Mapping[str, Sequence[tuple[str, str]]],
    settings: StatisticsConfig,
    segments: Sequence[int] | None = None,
) -> dict[str, list[dict[str, Any]]]:
    """Every table of one season pair: each comparison's difference in fraction correct (first -
    second), interval, discordant counts, p-value, Holm p-value and verdict.
    outcome_of(label): that evaluation's (query places, correct) on the pair, in query order (read
    once per label). The queries are one route, or independent routes of segments[i] queries one
    after another (replicate routes pooled)."""
    loaded: dict[str, tuple[np.ndarray, np.ndarray]] = {}

    def correct(label: str) -> np.ndarray:
        if label not in loaded:
            loaded[label] = outcome_of(label)
            first_label, (first_places, _) = next(iter(loaded.items()))
            if not np.array_equal(loaded[label][0], first_places):
                raise ValueError(f"{label}: its queries are not those of {first_label} (rerun the evaluate stages)")
        return loaded[label][1]

    return {
        name: [
            {"first": first, "second": second, **row}
            for (first, second), row in zip(
                comparisons,
                table_verdicts(
                    [(correct(first), correct(second)) for first, second in comparisons], settings, segments
                ),
            )
        ]
        for name, comparisons in tables.items()
    }


def table_verdicts(
    compared: Sequence[tuple[np.ndarray, np.ndarray]], settings: StatisticsConfig, segments: Sequence[int] | None = None
) -> list[dict[str, Any]]:
    """paired_difference of each (first, second) outcome arrays of one table, the runs' persistence
    pooled over the table's differences (one kind of statement), with Holm's verdicts over the table."""
    runs = persistence(route for first, second in compared for route in routes_of(differences(first, second), segments))
    rows = [paired_difference(first, second, settings, segments, runs) for first, second in compared]
    return with_verdicts(rows, settings.alpha)
