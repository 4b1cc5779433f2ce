"""Stage training_seasons: the study's training-season effect (its Figure 18).

For each learner of ablation.methods and each list of ablation.training_seasons, fit the learner
on those seasons' training images and evaluate single-image matching on the fixed pair
ablation.pair. Writes metrics/training_seasons.json and plots/training_seasons.png.
"""

from __future__ import annotations

from pathlib import Path


from _common import data_seasons, load_params, param, stage_main, test_images, test_places, training_images

from seasonloop.config import check_seasons, parse_pair
from seasonloop.evaluation import match_pair
from seasonloop.io import write_json
from seasonloop.models.registry import get_learner
from seasonloop.plots import plot_series


@stage_main
def main() -> None:
    params = load_params()
    ablation = param(params, "ablation")
    seasons = data_seasons(params)
    database, query = parse_pair(ablation["pair"], "ablation.pair")
    for season in (database, query):
        if season not in seasons:
            raise ValueError(f"ablation.pair: season '{season}' is not in data.seasons")
    season_sets = [check_seasons(chosen, "ablation.training_seasons", allowed=seasons)
                   for chosen in ablation["training_seasons"]]
    places = test_places()
    test = test_images([database, query])
    labels = ["+".join(chosen) for chosen in season_sets]
    # fraction_correct[method][training seasons joined by "+"]
    fraction_correct: dict[str, dict[str, float]] = {}
    for method in ablation["methods"]:
        learner_class = get_learner(method)
        fraction_correct[method] = {}
        for label, chosen in zip(labels, season_sets):
            learner = learner_class(param(params, method), seed=int(param(params, "seed")))
            learner.fit(training_images(params, chosen), progress=True)
            metrics, _, _ = match_pair(learner.describe(test[database]), learner.describe(test[query]),
                                       places, places, "single", param(params, "evaluate"), param(params, "sequence"))
            fraction_correct[method][label] = metrics["fraction_correct"]
    write_json(Path("metrics/training_seasons.json"), {"pair": ablation["pair"], "fraction_correct": fraction_correct})
    plot_series({method: (labels, [100 * values[label] for label in labels]) for method, values in fraction_correct.items()},
                Path("plots/training_seasons.png"), title=f"Training-season effect on {ablation['pair']}",
                xlabel="training seasons", ylabel="fraction correct (%)")


if __name__ == "__main__":
    main()
