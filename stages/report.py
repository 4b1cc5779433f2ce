"""Stage report: every result of the study in one self-contained HTML file, plots/report.html.

Reads the other stages' metrics and figures, recomputes the single-image best matches of
report.example_pair to show example matches and failures, and embeds params.yaml verbatim.
"""

from __future__ import annotations

from pathlib import Path


from _common import PARAMS_FILE, data_seasons, load_params, param, stage_main, test_images, test_places

from seasonloop.config import available_pairs, pair_name, pair_present
from seasonloop.evaluation import evaluations
from seasonloop.io import load_array, read_json, staged_file
from seasonloop.matching import distance_matrix
from seasonloop.report import (
    build_report,
    autoencoder_training_section,
    dataset_section,
    example_grid_png,
    examples_section,
    figures_section,
    fraction_correct_section,
    parameters_section,
    pr_section,
    runtime_section,
    select_examples,
    similarity_section,
    training_seasons_section,
)
from seasonloop.summary import pr_landmarks, pr_landmarks_table

N_EXAMPLES = 3  # correct matches, and as many failures, shown per learner


def ordered(mapping: dict, keys: list[str], source: str) -> dict:
    """mapping's entries in the order of keys (the JSON files store their keys sorted)."""
    missing = [key for key in keys if key not in mapping]
    if missing:
        raise ValueError(f"{source}: no entry for {', '.join(missing)} (rerun the stage that writes it)")
    return {key: mapping[key] for key in keys}


@stage_main
def main() -> None:
    params = load_params("learners", "data.seasons", "evaluate", "ablation", "report")
    methods = list(param(params, "learners"))
    matchers = list(param(params, "evaluate.matchers"))
    evaluate = param(params, "evaluate")
    seasons = data_seasons(params)
    pairs = [pair_name(a, b) for a, b in available_pairs(seasons, param(params, "evaluate.pairs"))]
    (database, query), note = pair_present(param(params, "report.example_pair"), seasons,
                                           param(params, "evaluate.pairs"), "report.example_pair")
    if note:
        print(f"report: {note}")

    results = {method + suffix: {pair: read_json(Path("metrics/eval") / method / f"{pair}{suffix}.json")
                                 for pair in pairs}
               for _, _, suffix in evaluations(evaluate) for method in methods}
    extra_metrics = list(evaluate["extra_metrics"])

    places = test_places()
    images = test_images([database, query])
    example_pair = pair_name(database, query)
    grids = {}
    for method in methods:
        features = Path("data/features") / method
        distances = distance_matrix(load_array(features / f"{database}.npy"), load_array(features / f"{query}.npy"),
                                    metric=evaluate["metric"])
        examples = select_examples(distances, places, places, evaluate["confidence"],
                                   int(evaluate["tolerance_frames"]), N_EXAMPLES, int(evaluate["ratio_exclusion"]))
        grids[method] = example_grid_png(images[database], images[query], examples, places, places,
                                         title=f"{method}: {query} queries vs {database} database")

    dataset = read_json(Path("metrics/dataset.json"))
    dataset["seasons"] = ordered(dataset["seasons"], seasons, "metrics/dataset.json")
    runtime = ordered(read_json(Path("metrics/runtime.json")), methods, "metrics/runtime.json")
    training = read_json(Path("metrics/training_seasons.json"))
    if "skipped" not in training:
        # the lists the ablation ran (adapted to the seasons present), in their order
        training["fraction_correct"] = {
            method: ordered(values, training["season_sets"], "metrics/training_seasons.json")
            for method, values in ordered(training["fraction_correct"], list(param(params, "ablation.methods")),
                                          "metrics/training_seasons.json").items()}
    autoencoders = read_json(Path("metrics/autoencoder_descriptors.json"))
    autoencoders = ordered(autoencoders, [method for method in methods if method in autoencoders],
                           "metrics/autoencoder_descriptors.json")
    autoencoder_training = read_json(Path("metrics/autoencoder_training.json"))
    if not Path("plots/figures").is_dir():
        raise FileNotFoundError("plots/figures: not found (run the figures stage first)")
    # the figures stage draws only those whose learners are in learners
    figures = sorted(Path("plots/figures").glob("*.png"))

    sections = [
        dataset_section(dataset, Path("plots/season_preview.png")),
        fraction_correct_section(results, methods, matchers, pairs, Path("plots/summary/fraction_correct.png"),
                                 extra_metrics, {metric: Path(f"plots/summary/fraction_correct@{metric}.png")
                                                 for metric in extra_metrics}),
        pr_section({pair: Path("plots/summary") / f"pr_{pair}.png" for pair in pairs},
                   pr_landmarks_table(pr_landmarks(results))),
        similarity_section({method: {pair: Path("plots/similarity") / method / f"{pair}.png" for pair in pairs}
                            for method in methods}, pairs),
        examples_section(example_pair, grids),
        runtime_section(runtime),
        training_seasons_section(training, Path("plots/training_seasons.png")),
        autoencoder_training_section(autoencoder_training),
        figures_section({path.stem.replace("_", " "): path for path in figures}, autoencoders),
        parameters_section(PARAMS_FILE.read_text()),
    ]
    with staged_file(Path("plots/report.html")) as tmp:
        tmp.write_text(build_report("seasonloop: loop-closure detection across seasons", sections), encoding="utf-8")


if __name__ == "__main__":
    main()
