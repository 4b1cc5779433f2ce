"""The training-season ablation (study Figure 18) fitted to the seasons a run actually has.

The study's defaults name all four seasons; a run on a subset (one real pair, say) keeps what it
can: the pair if both its seasons are present, else the first of evaluate.pairs that is; each list
of training seasons cut to the seasons present, repeats dropped. With fewer than two seasons
there is no pair to evaluate, and on a whole route (split.test_fraction 1) no list may hold the
pair's query traverse; an ablation left with nothing to compare is skipped, with the reason. run_ablation fits and
evaluates the plan, one learner at a time (one pipeline stage per learner, so that a learner's
change refits only its own ablation); write_learner_record keeps each learner's result, which
training_season_records.py reads back into the combined record and figure. A label of fewer
seasons than a learner's min_traverses is not fitted (a place-supervised learner needs a place seen
in two traverses): its value is None and the records say why.

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
from seasonloop.io import write_json
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
    matching (None where the learner cannot train on the label's seasons), and its interval along
    the route {low, high}; per learner and label how its fit ended (the learner's how_fit_ended),
    and why a label was not fitted (not_fitted: a place-supervised learner on one traverse)."""

    fraction_correct: dict[str, dict[str, float | None]]
    intervals: dict[str, dict[str, dict[str, float]]]
    fits: dict[str, dict[str, dict[str, Any]]]
    not_fitted: dict[str, dict[str, str]] = field(default_factory=dict)


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
    skip[name] names a label that is not fitted (a reused one); a label of fewer seasons than the
    learner's min_traverses is not fitted either, its value None and its reason in not_fitted."""
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
            needs = getattr(learner, "min_traverses", 1)
            if len(chosen) < needs:
                for metric in metrics_used:
                    run.fraction_correct[name + result_suffix(metric, "single", evaluate)][label] = None
                run.not_fitted.setdefault(name, {})[label] = (
                    f"not fitted: {name} trains on {needs} traverses or more (places seen in other conditions)"
                )
                continue
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
            **({"not_fitted": run.not_fitted[learner]} if learner in run.not_fitted else {}),
        },
    )
