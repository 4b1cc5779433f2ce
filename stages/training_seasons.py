"""Stage training_seasons: the study's training-season effect (its Figure 18).

For each learner of ablation.methods and each list of ablation.training_seasons, fit the learner
on those seasons' training images and evaluate single-image matching on the fixed pair
ablation.pair. Writes metrics/training_seasons.json and plots/training_seasons.png. On a subset of
seasons the pair and lists adapt to the seasons present (seasonloop.ablations.training_seasons says how); with fewer
than two seasons the ablation is skipped and both files say why.
"""

from __future__ import annotations

import functools
from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from _datasets import test_images, test_places, training_images, training_places
from seasonloop.ablations.training_seasons import plan_ablation, run_ablation, write_ablation
from seasonloop.models.registry import get_learner
from seasonloop.params.settings import AblationConfig, EvaluateConfig, SequenceConfig

RECORD = Path("metrics/training_seasons.json")
FIGURE = Path("plots/training_seasons.png")


@stage_main
def main() -> None:
    params = load_params(
        "seed", "data.seasons", "train.augmented", "augment.copies", "ablation", "evaluate", "sequence"
    )
    ablation = AblationConfig.from_params(params)
    evaluate = EvaluateConfig.from_params(params)
    plan = plan_ablation(data_seasons(params), ablation.pair, ablation.training_seasons, evaluate.pairs)
    for note in plan.notes:
        print(f"training_seasons: {note}")
    if plan.skipped:
        print(f"training_seasons: {plan.skipped}")
        write_ablation(plan, None, RECORD, FIGURE)
        return
    # a fresh, unfitted learner per fit, built from the learner's own section
    new_learners = {
        method: functools.partial(get_learner(method), param(params, method), seed=int(param(params, "seed")))
        for method in ablation.methods
    }
    # every learner checks its section before the first (possibly long) fit
    for new_learner in new_learners.values():
        new_learner()
    fraction_correct = run_ablation(
        plan,
        new_learners,
        lambda seasons: (training_images(params, seasons), training_places(params, seasons)),
        test_images(list(plan.pair)),
        test_places(),
        evaluate,
        SequenceConfig.from_params(params),
    )
    write_ablation(plan, fraction_correct, RECORD, FIGURE)


if __name__ == "__main__":
    main()
