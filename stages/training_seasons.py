"""Stage training_seasons: the study's training-season effect (its Figure 18), from the records of
training_seasons_fit@<learner> for every learner of ablation.learners, and for the list of training
seasons that is the pipeline's own training set, evaluate@<learner>'s fraction correct (where the
fit stage reused it: not with split.folds > 1, whose evaluate pools every fold's queries).

Writes metrics/training_seasons.json and plots/training_seasons.png. With fewer than two seasons
the ablation is skipped and both files say why.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from seasonloop.ablations.training_season_records import (
    read_learner_intervals,
    read_learner_records,
    read_not_fitted,
    write_ablation,
)
from seasonloop.ablations.training_seasons import plan_ablation
from seasonloop.params.settings import AblationConfig, EvaluateConfig

RECORDS = Path("metrics/training_seasons")
EVALUATIONS = Path("metrics/eval")
RECORD = Path("metrics/training_seasons.json")
FIGURE = Path("plots/training_seasons.png")


@stage_main
def main() -> None:
    params = load_params("data.seasons", "ablation", "evaluate", "split.test_fraction")
    ablation = AblationConfig.from_params(params)
    evaluate = EvaluateConfig.from_params(params)
    whole_route = param(params, "split.test_fraction") == 1
    plan = plan_ablation(data_seasons(params), ablation.pair, ablation.training_seasons, evaluate.pairs, whole_route)
    if plan.skipped:
        print(f"training_seasons: {plan.skipped}")
        write_ablation(plan, None, RECORD, FIGURE)
        return
    fraction_correct = read_learner_records(plan, ablation.learners, RECORDS, EVALUATIONS)
    intervals = read_learner_intervals(plan, ablation.learners, RECORDS, EVALUATIONS)
    not_fitted = read_not_fitted(ablation.learners, RECORDS)
    write_ablation(plan, fraction_correct, RECORD, FIGURE, intervals, not_fitted)


if __name__ == "__main__":
    main()
