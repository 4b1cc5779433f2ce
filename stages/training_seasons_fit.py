"""Stage training_seasons_fit@<learner>: one learner's part of the training-season effect (Figure 18).

For each list of ablation.training_seasons, fit the learner on those seasons' training images and
evaluate single-image matching on the fixed pair ablation.pair; writes
metrics/training_seasons/<learner>.json. One stage per learner of ablation.learners, so that a change
to one learner (its module or its params) refits only its own ablation. On a subset of seasons the
pair and lists adapt to the seasons present (seasonloop.ablations.training_seasons says how); with
fewer than two seasons the record says why nothing was fitted. The list that is the pipeline's own
training set is not refitted: the training_seasons stage reads evaluate@<learner>'s number for it.
The ablation fits and tests on the study's split; with split.folds K > 1 evaluate@<learner> pools
every fold's queries, so that list is fitted here too.
"""

from __future__ import annotations

import argparse
import functools
from pathlib import Path

from _common import data_seasons, load_params, param, stage_main, train_seasons
from _datasets import SPLIT, test_images, training_images, training_places, training_traverses
from _ground_truth import evaluation_context, pair_truths
from seasonloop.ablations.training_seasons import plan_ablation, reusable_label, run_ablation, write_learner_record
from seasonloop.data.datasets import count_folds
from seasonloop.models.core.lookup import get_learner
from seasonloop.params.seasons import available_pairs
from seasonloop.params.settings import AblationConfig, EvaluateConfig

RECORDS = Path("metrics/training_seasons")


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("learner", help="a learner of ablation.learners")
    learner = parser.parse_args().learner
    params = load_params(
        "seed",
        "data.seasons",
        "learners",
        "train.seasons",
        "train.augmented",
        "augment.copies",
        "features",
        "ablation",
        "evaluate",
        "sequence",
        "statistics",
        "split.test_fraction",
    )
    ablation = AblationConfig.from_params(params)
    if learner not in ablation.learners:
        raise ValueError(f"ablation.learners: '{learner}' is not one of {list(ablation.learners)}")
    evaluate = EvaluateConfig.from_params(params)
    whole_route = param(params, "split.test_fraction") == 1
    plan = plan_ablation(data_seasons(params), ablation.pair, ablation.training_seasons, evaluate.pairs, whole_route)
    for note in plan.notes:
        print(f"training_seasons_fit@{learner}: {note}")
    record = RECORDS / f"{learner}.json"
    if plan.skipped:
        print(f"training_seasons_fit@{learner}: {plan.skipped}")
        write_learner_record(plan, learner, None, record)
        return
    # a fresh, unfitted learner per fit, built from the learner's own section (built once here so
    # that it checks its section before the first, possibly long, fit)
    new_learner = functools.partial(get_learner(learner), param(params, learner), seed=int(param(params, "seed")))
    new_learner()
    reused = reusable_label(
        plan,
        train_seasons(params),
        learner in param(params, "learners"),
        # evaluate@<learner> of a run of several folds holds every fold's queries, not the study split's
        plan.pair in available_pairs(data_seasons(params), evaluate.pairs) and count_folds(SPLIT) == 1,
    )
    if reused:
        print(
            f"training_seasons_fit@{learner}: {reused} is fit@{learner}'s training set: evaluate@{learner}'s result is used"
        )
    context = evaluation_context(params, test_images(list(plan.pair)), pair_truths([plan.pair]), [plan.pair])
    run = run_ablation(
        plan,
        {learner: new_learner},
        lambda seasons: (
            training_images(params, seasons),
            training_places(params, seasons),
            training_traverses(params, seasons),
        ),
        context,
        skip={learner: reused},
    )
    write_learner_record(plan, learner, run, record, reused)


if __name__ == "__main__":
    main()
