"""The training-season ablation (study Figure 18) fitted to the seasons a run actually has.

The study's defaults name all four seasons; a run on a subset (one real pair, say) keeps what it
can: the pair if both its seasons are present, else the first of evaluate.pairs that is; each list
of training seasons cut to the seasons present, repeats dropped. With fewer than two seasons
there is no pair to evaluate, and on a whole route (split.test_fraction 1) no list may hold the
pair's query traverse; an ablation left with nothing to compare is skipped, with the reason. run_ablation fits and
evaluates the plan, one learner at a time (one pipeline stage per learner, so that a learner's
change refits only its own ablation); write_learner_record and read_learner_records keep each
learner's result, write_ablation writes the combined record and figure.

Reuse: a list of training seasons that is the pipeline's own training set (train.seasons, as a set:
the training images are concatenated in data.seasons order whatever the list's order) gives the
learner fit@<learner> fits, on the same images in the same order with the same params and seed,
so its fraction correct is the one evaluate@<learner> wrote for the pair (same descriptors, same
batches, same matching); `reusable_label` names that list and it is read back instead of refitted
(`fill_reused`). At the study's scale this saves one ICA fit of the four.

Distances: each fit is evaluated under evaluate.metric and every evaluate.extra_metrics, as the
pipeline's tables are; a series is named as their rows, "<learner>" and "<learner>@<metric>", so
that under L1 (not rotation invariant) the effect on ICA is told from the effect on its whitening.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.evaluation.blocks import evaluate_descriptors
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.evaluation.matchers import result_suffix
from seasonloop.io import read_json, write_json
from seasonloop.params.seasons import SEASONS, check_seasons, pair_name, pair_present, parse_pair
from seasonloop.significance.intervals import route_intervals


@dataclass(frozen=True)
class AblationPlan:
    pair: tuple[str, str] | None  # None when skipped
    season_sets: list[list[str]]
    notes: list[str] = field(default_factory=list)  # what was adapted, one line each
    skipped: str | None = None  # why nothing is fitted

    @property
    def labels(self) -> list[str]:
        return ["+".join(chosen) for chosen in self.season_sets]


def plan_ablation(
    seasons: Sequence[str],
    pair: str,
    training_seasons: Sequence[Sequence[str]],
    evaluate_pairs: Sequence[str],
    whole_route: bool = False,
) -> AblationPlan:
    """The pair and training-season lists to run with `seasons` present (the module doc); on a
    whole route (split.test_fraction 1) without the lists that hold the pair's query traverse."""
    parse_pair(pair, "ablation.pair", known=seasons)
    # names are checked against the data's and the study's seasons, so a typo is an error, not a
    # silently dropped list
    known = list(dict.fromkeys([*seasons, *SEASONS]))
    requested = [check_seasons(chosen, "ablation.training_seasons", allowed=known) for chosen in training_seasons]
    if not requested:
        raise ValueError("ablation.training_seasons: expected a non-empty list of season lists")
    if len(seasons) < 2:
        return AblationPlan(
            None, [], skipped=f"skipped: it needs two seasons and data.seasons has only {list(seasons)}"
        )
    (database, query), note = pair_present(pair, seasons, evaluate_pairs, "ablation.pair")
    notes = [note] if note else []
    season_sets: list[list[str]] = []
    for chosen in requested:
        kept = [season for season in chosen if season in seasons]
        if kept and kept not in season_sets:
            season_sets.append(kept)
    dropped = [chosen for chosen in requested if [s for s in chosen if s in seasons] != chosen]
    if dropped:
        notes.append(
            "ablation.training_seasons: seasons not in data.seasons left out of "
            + ", ".join("+".join(chosen) for chosen in dropped)
        )
    if not season_sets:
        return AblationPlan(
            None, [], notes, skipped="skipped: no list of ablation.training_seasons has a season of data.seasons"
        )
    if whole_route:  # every place tested and trained on: no list may hold the query traverse
        held = [chosen for chosen in season_sets if query in chosen]
        season_sets = [chosen for chosen in season_sets if query not in chosen]
        if held:
            notes.append(f"ablation.training_seasons: {', '.join('+'.join(c) for c in held)} left out: {query} is the "
                         "query traverse, and split.test_fraction 1 trains on every place")  # fmt: skip
        if len(season_sets) < 2:
            left = "+".join(season_sets[0]) if season_sets else "none"
            skipped = f"skipped: it compares training sets, and with split.test_fraction 1 and {query} the query "
            return AblationPlan(None, [], notes, skipped=skipped + f"traverse one is left at most ({left})")
    return AblationPlan((database, query), season_sets, notes)


def reusable_label(
    plan: AblationPlan, train_seasons: Sequence[str], in_pipeline: bool, pair_evaluated: bool
) -> str | None:
    """The label of the plan's list whose seasons are the pipeline's training set (module doc), when
    the learner is one of the pipeline's (in_pipeline) and its evaluate stage matches the plan's
    pair (pair_evaluated); else None."""
    if not (in_pipeline and pair_evaluated):
        return None
    for label, chosen in zip(plan.labels, plan.season_sets):
        if set(chosen) == set(train_seasons):
            return label
    return None


@dataclass(frozen=True)
class AblationRun:
    """What run_ablation found, per series (a learner under one distance: "<learner>" under
    evaluate.metric, "<learner>@<metric>" under each of evaluate.extra_metrics) and training-season
    label (the seasons joined by "+"): the fraction correct on the plan's pair, single-image
    matching, and its interval along the route {low, high}; and per learner and label how its fit
    ended (the learner's how_fit_ended)."""

    fraction_correct: dict[str, dict[str, float]]
    intervals: dict[str, dict[str, dict[str, float]]]
    fits: dict[str, dict[str, dict[str, Any]]]


def run_ablation(
    plan: AblationPlan,
    new_learners: Mapping[str, Callable[[], Any]],
    training_set: Callable[[list[str]], tuple[np.ndarray, np.ndarray, np.ndarray]],
    context: EvaluationContext,
    skip: Mapping[str, str | None] | None = None,
) -> AblationRun:
    """For each learner name (new_learners[name]() gives an unfitted learner) and each list of the plan,
    a learner fitted on training_set(list) = (images, the place id and the traverse of each image),
    evaluated on the plan's pair. The place ids go to fit, so that an auto-encoder holds out whole
    places (every season and augmented copy of them) for validation, and with the traverses a
    place-supervised learner knows which images show one place in other conditions. The context's test images are those of the
    pair's seasons, at the test places of its truth, described in the features stage's batches.
    skip[name] names a label that is not fitted (a reused one)."""
    assert plan.pair is not None and plan.labels is not None and plan.season_sets is not None, "a skipped plan"
    database, query = plan.pair
    truth, evaluate = context.truths[plan.pair], context.evaluate
    run = AblationRun({}, {}, {})
    correct: dict[str, dict[str, np.ndarray]] = {}
    metrics_used = [evaluate.metric, *evaluate.extra_metrics]
    for name, new_learner in new_learners.items():
        for metric in metrics_used:
            run.fraction_correct[name + result_suffix(metric, "single", evaluate)] = {}
        for label, chosen in zip(plan.labels, plan.season_sets):
            if (skip or {}).get(name) == label:
                continue
            learner = new_learner()
            images, image_places, image_traverses = training_set(chosen)
            info = learner.fit(images, progress=True, places=image_places, traverses=image_traverses)
            run.fits.setdefault(name, {})[label] = learner.how_fit_ended(info)
            database_descriptors, query_descriptors = (
                learner.describe(context.test[season], batch_size=context.batch_size) for season in (database, query)
            )
            for metric in metrics_used:
                series = name + result_suffix(metric, "single", evaluate)
                evaluation = evaluate_descriptors(
                    database_descriptors, query_descriptors, truth, "single", evaluate, context.sequence, metric=metric
                )
                run.fraction_correct[series][label] = evaluation.metrics["fraction_correct"]
                correct.setdefault(series, {})[label] = evaluation.outcomes.correct
    run.intervals.update({series: route_intervals(labels, context.statistics) for series, labels in correct.items()})
    return run


def write_ablation(
    plan: AblationPlan,
    fraction_correct: dict[str, dict[str, float]] | None,
    record: Path,
    figure: Path,
    intervals: Mapping[str, Mapping[str, Mapping[str, float]]] | None = None,
) -> None:
    """The ablation's JSON record and its figure (study Fig. 18), each fraction correct with its
    interval (intervals[series][label] = {low, high}) where given; for a skipped plan, both say why."""
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
        },
    )
    plot_series(
        {
            series: (plan.labels, [100 * values[label] for label in plan.labels])
            for series, values in fraction_correct.items()
        },
        figure,
        title=f"Training-season effect on {pair} (bars: 95% intervals)"
        if intervals
        else f"Training-season effect on {pair}",
        xlabel="training seasons",
        ylabel="fraction correct (%)",
        bands={series: percent_bands([bounds[label] for label in plan.labels]) for series, bounds in intervals.items()},
    )


def write_learner_record(
    plan: AblationPlan, learner: str, run: AblationRun | None, record: Path, reused: str | None = None
) -> None:
    """One learner's part of the ablation: run_ablation's fraction correct, intervals and fits of
    `learner` on the plan's pair (None for a skipped plan, whose record says why); `reused` is the
    label left to fill_reused."""
    if plan.skipped:
        write_json(record, {"skipped": plan.skipped})
        return
    assert plan.pair is not None and run is not None
    write_json(
        record,
        {
            "pair": pair_name(*plan.pair),
            "fraction_correct": {series: dict(values) for series, values in run.fraction_correct.items()},
            "reused_from_pipeline": [reused] if reused else [],
            "fits": {label: dict(ended) for label, ended in run.fits.get(learner, {}).items()},
            "intervals": {series: dict(bounds) for series, bounds in run.intervals.items()},
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
            if set(intervals[name]) != set(plan.labels):
                raise ValueError(f"{folder / learner}.json: no interval for every season list (rerun its stage)")
    return intervals


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
