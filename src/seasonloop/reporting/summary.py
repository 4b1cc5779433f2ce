"""Tables of the study built from the per-pair metrics: fraction correct, runtimes."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.reporting.study import STUDY_FRACTION_CORRECT, STUDY_PR_LANDMARKS
from seasonloop.significance.intervals import RUNS_TOO_LONG


def fraction_correct_table(
    results: Mapping[str, Mapping[str, Mapping[str, float]]], pairs: Sequence[str]
) -> pd.DataFrame:
    """results[label][pair] = metrics dict -> DataFrame (labels x pairs) of fraction correct in %."""
    return pd.DataFrame(
        {
            pair: [
                100 * results[label][pair]["fraction_correct"] if pair in results[label] else np.nan
                for label in results
            ]
            for pair in pairs
        },
        index=list(results),
    )


def interval_tables(
    results: Mapping[str, Mapping[str, Mapping[str, Any]]], pairs: Sequence[str]
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(low, high) DataFrames like fraction_correct_table's, in %: each fraction correct's 95%
    interval along the route (seasonloop.significance.intervals; NaN where a pair has no metrics or
    too few queries for an interval)."""

    def bound(label: str, pair: str, side: str) -> float:
        if pair not in results[label]:
            return np.nan
        value = results[label][pair]["intervals"]["fraction_correct"]["route"][side]
        return np.nan if value is None else 100 * value

    low, high = (
        pd.DataFrame({pair: [bound(label, pair, side) for label in results] for pair in pairs}, index=list(results))
        for side in ("low", "high")
    )
    return low, high


def study_table(labels: Sequence[str], pairs: Sequence[str]) -> pd.DataFrame:
    """The study's fraction correct (%) in the same shape, NaN where it gives no number."""
    return pd.DataFrame(
        {pair: [STUDY_FRACTION_CORRECT.get(label, {}).get(pair, np.nan) for label in labels] for pair in pairs},
        index=list(labels),
    )


def markdown_table(table: pd.DataFrame, index_name: str) -> str:
    """A markdown table of `table`'s cells as they print (format numbers before calling)."""
    lines = [f"| {index_name} | " + " | ".join(map(str, table.columns)) + " |", "|" + "---|" * (len(table.columns) + 1)]
    lines += [f"| {label} | " + " | ".join(map(str, row)) + " |" for label, row in zip(table.index, table.to_numpy())]
    return "\n".join(lines) + "\n"


# where a route is too short for an interval (seasonloop.significance.intervals.MIN_DEGREES), or
# too short for its runs (the interval's reason begins with intervals.RUNS_TOO_LONG)
NO_INTERVAL = "[not enough queries]"
LONG_RUNS = "[runs too long]"


def with_interval(percent: float, low: float | None = None, high: float | None = None) -> str:
    """'81.0 [69, 94]': a fraction correct in % with its interval's ends (in %, whole percent: they
    are not known to a tenth) where it has one; low None: the value alone (no interval asked for);
    low NaN: the value and NO_INTERVAL (too few queries for one)."""
    if low is None or high is None:
        return f"{percent:.1f}"
    if not np.isfinite(low):
        return f"{percent:.1f} {NO_INTERVAL}"
    return f"{percent:.1f} [{low:.0f}, {high:.0f}]"


def percent_cell(value: float | None, interval: Mapping[str, float | None] | None = None) -> str:
    """with_interval's cell of a fraction (not %) and its interval {low, high} (fractions; low None
    where the route was too short for one: LONG_RUNS where its runs made it so) where it has one;
    "n/a" where there is no value (a learner not fitted on a training set it cannot learn from)."""
    if value is None:
        return "n/a"
    if not interval:
        return with_interval(100 * value)
    low, high = interval["low"], interval["high"]
    if low is None or high is None:
        if str(interval.get("reason", "")).startswith(RUNS_TOO_LONG):
            return f"{100 * value:.1f} {LONG_RUNS}"
        return with_interval(100 * value, np.nan, np.nan)
    return with_interval(100 * value, 100 * low, 100 * high)


def record_cell(record: Mapping[str, Any], pair: str) -> str:
    """percent_cell of a pair in a record {fraction_correct: {pair: value}, interval: {pair: {low,
    high}}} (seasonloop.reporting.figures.fraction_correct_record's; interval optional)."""
    return percent_cell(record["fraction_correct"][pair], record.get("interval", {}).get(pair))


def side_by_side_markdown(
    ours: pd.DataFrame, study: pd.DataFrame, intervals: tuple[pd.DataFrame, pd.DataFrame] | None = None
) -> str:
    """Each cell 'ours [low, high] (study)': the interval where `intervals` has one (whole percent:
    its ends are not known to a tenth), the study's number only where it gives one."""
    cells = ours.map(lambda value: "n/a" if np.isnan(value) else f"{value:.1f}")
    if intervals is not None:
        low, high = (bound.loc[ours.index, ours.columns] for bound in intervals)
        for label in ours.index:
            for pair in ours.columns:
                if not np.isnan(ours.loc[label, pair]):
                    cells.loc[label, pair] = with_interval(
                        ours.loc[label, pair], low.loc[label, pair], high.loc[label, pair]
                    )
    for label in ours.index.intersection(study.index):
        for pair in ours.columns:
            if not np.isnan(study.loc[label, pair]):
                cells.loc[label, pair] += f" ({study.loc[label, pair]:.0f})"
    return markdown_table(cells, "learner")


LANDMARK_NAMES = {
    "recall_at_100_precision": "recall at 100% precision",
    "precision_at_full_recall": "precision at 100% recall",
}


def pr_landmarks(results: Mapping[str, Mapping[str, Mapping[str, float]]]) -> dict[str, dict[str, dict[str, dict]]]:
    """The study's PR landmarks (STUDY_PR_LANDMARKS) beside ours: pair -> learner -> metric key ->
    {"ours": fraction or None where we did not evaluate that pair or learner, "study": fraction}.
    results[label][pair] = metrics dict; the study's numbers are single-image matching, under its
    learners' plain labels ('pca', 'ica')."""
    return {
        pair: {
            learner: {
                key: {
                    "ours": results[learner][pair][key] if pair in results.get(learner, {}) else None,
                    "study": study_value,
                }
                for key, study_value in landmarks.items()
            }
            for learner, landmarks in by_learner.items()
        }
        for pair, by_learner in STUDY_PR_LANDMARKS.items()
    }


def pr_landmarks_table(landmarks: Mapping[str, Mapping[str, Mapping[str, Mapping[str, float | None]]]]) -> pd.DataFrame:
    """pr_landmarks' record as a table in %: rows (pair, learner, landmark), columns ours, study (S)."""
    rows = {
        (pair, learner, LANDMARK_NAMES[key]): {
            "ours": np.nan if values["ours"] is None else 100 * values["ours"],
            "study (S)": 100 * float(values["study"]),  # type: ignore[arg-type]  # the study states each landmark
        }
        for pair, by_learner in landmarks.items()
        for learner, by_key in by_learner.items()
        for key, values in by_key.items()
    }
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index.names = ["pair", "learner", "landmark"]
    return table
