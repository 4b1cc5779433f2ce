"""The training-season ablation's records (seasonloop.ablations.training_seasons runs it): each
learner's record read back and checked against the plan, a reused label's value and interval from
the evaluate stage's record, and the combined record and figure (study Fig. 18)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.ablations.training_seasons import AblationPlan
from seasonloop.io import read_json, write_json
from seasonloop.params.seasons import pair_name


def write_ablation(
    plan: AblationPlan,
    fraction_correct: dict[str, dict[str, float | None]] | None,
    record: Path,
    figure: Path,
    intervals: Mapping[str, Mapping[str, Mapping[str, float]]] | None = None,
    not_fitted: Mapping[str, Mapping[str, str]] | None = None,
) -> None:
    """The ablation's JSON record and its figure (study Fig. 18), each fraction correct with its
    interval (intervals[series][label] = {low, high}) where given, and why a learner was not fitted on
    a label (not_fitted[learner][label]; its value None, no point drawn); for a skipped plan, both
    say why."""
    # imported here: matplotlib is ~0.25 s of every training_seasons_fit process, which draws nothing
    from seasonloop.plots import percent_bands, plot_message, plot_series

    if plan.skipped:
        write_json(record, {"skipped": plan.skipped})
        plot_message(figure, f"Training-season effect {plan.skipped}")
        return
    assert plan.pair is not None and plan.labels is not None and fraction_correct is not None
    pair = pair_name(*plan.pair)
    # season_sets keeps the order (the JSON's keys are sorted)
    intervals = intervals or {}
    write_json(
        record,
        {
            "pair": pair,
            "season_sets": plan.labels,
            "notes": plan.notes,
            "fraction_correct": fraction_correct,
            "intervals": intervals,
            # only where a learner could not train on a label: records of every other run unchanged
            **({"not_fitted": dict(not_fitted)} if not_fitted else {}),
        },
    )
    unfitted = {"low": None, "high": None}  # no interval, no bar
    plot_series(
        {
            series: (
                plan.labels,
                [np.nan if (value := values[label]) is None else 100 * value for label in plan.labels],
            )
            for series, values in fraction_correct.items()
        },
        figure,
        title=f"Training-season effect on {pair} (bars: 95% intervals)"
        if intervals
        else f"Training-season effect on {pair}",
        xlabel="training seasons",
        ylabel="fraction correct (%)",
        bands={
            series: percent_bands([bounds.get(label, unfitted) for label in plan.labels])
            for series, bounds in intervals.items()
        },
    )


def read_learner_records(
    plan: AblationPlan, learners: Sequence[str], folder: Path, eval_dir: Path
) -> dict[str, dict[str, float]]:
    """fraction_correct[series][label] from folder/<learner>.json of every learner, each checked to
    hold the plan's pair and season lists (a record of another plan is a stale input); a reused
    label's value from eval_dir (fill_reused)."""
    assert plan.pair is not None
    fraction_correct: dict[str, dict[str, float]] = {}
    for learner in learners:
        path = folder / f"{learner}.json"
        if not path.is_file():
            raise FileNotFoundError(f"{path}: not found (run the stage training_seasons_fit@{learner} first)")
        record = read_json(path)
        reused = set(record.get("reused_from_pipeline", []))
        series = record.get("fraction_correct", {})
        # JSON keys are sorted: compare the season lists as sets
        stale = not series or any(set(values) | reused != set(plan.labels) for values in series.values())
        if record.get("pair") != pair_name(*plan.pair) or stale:
            raise ValueError(f"{path}: written for another ablation plan than {pair_name(*plan.pair)} on {plan.labels}")
        for name, values in series.items():
            fraction_correct[name] = dict(values)
            for label in reused:
                fraction_correct[name][label] = fill_reused(name, pair_name(*plan.pair), eval_dir)
    return fraction_correct


def read_learner_intervals(
    plan: AblationPlan, learners: Sequence[str], folder: Path, eval_dir: Path
) -> dict[str, dict[str, dict[str, float]]]:
    """intervals[series][label] = {low, high} from the records read_learner_records has checked; a
    reused label's from the interval evaluate@<learner> wrote beside its fraction correct."""
    assert plan.pair is not None
    intervals: dict[str, dict[str, dict[str, float]]] = {}
    for learner in learners:
        record = read_json(folder / f"{learner}.json")
        for name in record["fraction_correct"]:
            intervals[name] = dict(record.get("intervals", {}).get(name, {}))
            for label in record.get("reused_from_pipeline", []):
                intervals[name][label] = reused_metrics(name, pair_name(*plan.pair), eval_dir)["intervals"][
                    "fraction_correct"
                ]["route"]
            if set(intervals[name]) | set(record.get("not_fitted", {})) != set(plan.labels):
                raise ValueError(f"{folder / learner}.json: no interval for every season list (rerun its stage)")
    return intervals


def read_not_fitted(learners: Sequence[str], folder: Path) -> dict[str, dict[str, str]]:
    """not_fitted[learner][label]: why a learner's record holds no fit for a label (empty for the
    learners that fitted every one)."""
    records = {learner: read_json(folder / f"{learner}.json") for learner in learners}
    return {learner: record["not_fitted"] for learner, record in records.items() if record.get("not_fitted")}


def fill_reused(series: str, pair: str, eval_dir: Path) -> float:
    """The single-image fraction correct that evaluate@<learner> wrote for `pair` under the series'
    distance ("<learner>": evaluate.metric, "<learner>@<metric>": that one): the ablation's value for
    the pipeline's own training set (module doc)."""
    return float(reused_metrics(series, pair, eval_dir)["fraction_correct"])


def reused_metrics(series: str, pair: str, eval_dir: Path) -> dict[str, Any]:
    """The metrics evaluate@<learner> wrote for `pair` under the series' distance (single images)."""
    learner, _, metric = series.partition("@")
    path = eval_dir / learner / f"{pair}{'@' + metric if metric else ''}.json"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: not found (run the stage evaluate@{learner} first)")
    return read_json(path)
