"""Stage training_seasons: the study's training-season effect (its Figure 18).

For each learner of ablation.methods and each list of ablation.training_seasons, fit the learner
on those seasons' training images and evaluate single-image matching on the fixed pair
ablation.pair. Writes metrics/training_seasons.json and plots/training_seasons.png. On a subset of
seasons the pair and lists adapt to the seasons present (seasonloop.ablation says how); with fewer
than two seasons the ablation is skipped and both files say why.
"""

from __future__ import annotations

from pathlib import Path


from _common import data_seasons, load_params, param, stage_main, test_images, test_places, training_images

from seasonloop.ablation import plan_ablation
from seasonloop.config import pair_name
from seasonloop.evaluation import match_pair
from seasonloop.io import write_json
from seasonloop.models.registry import get_learner
from seasonloop.plots import plot_message, plot_series


@stage_main
def main() -> None:
    params = load_params("seed", "data.seasons", "train.augmented", "ablation", "evaluate", "sequence")
    ablation = param(params, "ablation")
    plan = plan_ablation(data_seasons(params), ablation["pair"], ablation["training_seasons"],
                         param(params, "evaluate.pairs"))
    for note in plan.notes:
        print(f"training_seasons: {note}")
    if plan.skipped:
        print(f"training_seasons: {plan.skipped}")
        write_json(Path("metrics/training_seasons.json"), {"skipped": plan.skipped})
        plot_message(Path("plots/training_seasons.png"), f"Training-season effect {plan.skipped}")
        return
    database, query = plan.pair
    places = test_places()
    test = test_images([database, query])
    # fraction_correct[method][training seasons joined by "+"]
    fraction_correct: dict[str, dict[str, float]] = {}
    # every learner checks its section before the first (possibly long) fit
    learner_classes = {method: get_learner(method) for method in ablation["methods"]}
    for method, learner_class in learner_classes.items():
        learner_class(param(params, method), seed=int(param(params, "seed")))
    for method, learner_class in learner_classes.items():
        fraction_correct[method] = {}
        for label, chosen in zip(plan.labels, plan.season_sets):
            learner = learner_class(param(params, method), seed=int(param(params, "seed")))
            learner.fit(training_images(params, chosen), progress=True)
            metrics, _, _ = match_pair(learner.describe(test[database]), learner.describe(test[query]),
                                       places, places, "single", param(params, "evaluate"), param(params, "sequence"))
            fraction_correct[method][label] = metrics["fraction_correct"]
    pair = pair_name(database, query)
    # season_sets keeps the order (the JSON's keys are sorted)
    write_json(Path("metrics/training_seasons.json"), {"pair": pair, "season_sets": plan.labels,
                                                      "notes": plan.notes, "fraction_correct": fraction_correct})
    plot_series({method: (plan.labels, [100 * values[label] for label in plan.labels]) for method, values in fraction_correct.items()},
                Path("plots/training_seasons.png"), title=f"Training-season effect on {pair}",
                xlabel="training seasons", ylabel="fraction correct (%)")

if __name__ == "__main__":
    main()
