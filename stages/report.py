"""Stage report: every result of the study in one self-contained HTML file, plots/report.html.

Reads the other stages' metrics and figures, the single-image best matches of report.example_pair
from the evaluate stage's per-query outcomes to show example matches and failures, and embeds
params.yaml verbatim
(seasonloop.reporting.report assembles it).
"""

from __future__ import annotations

from pathlib import Path

from _common import PARAMS_FILE, data_seasons, load_params, param, stage_main
from _datasets import test_images
from _ground_truth import pair_truths
from seasonloop.evaluation.matchers import evaluations
from seasonloop.io import staged_file
from seasonloop.params.seasons import available_pairs, pair_name, pair_present
from seasonloop.params.settings import AblationConfig, EvaluateConfig, ReportConfig
from seasonloop.reporting.report import ReportFiles, study_report
from seasonloop.reporting.results import load_evaluations

FILES = ReportFiles(
    params=PARAMS_FILE,
    dataset=Path("metrics/dataset.json"),
    runtime=Path("metrics/runtime.json"),
    training_seasons=Path("metrics/training_seasons.json"),
    autoencoder_descriptors=Path("metrics/autoencoder_descriptors.json"),
    network_training=Path("metrics/network_training.json"),
    outcomes=Path("data/outcomes"),
    season_preview=Path("plots/season_preview.png"),
    summary=Path("plots/summary"),
    training_seasons_figure=Path("plots/training_seasons.png"),
    cae_widths=Path("metrics/cae_widths.json"),
    cae_widths_figure=Path("plots/cae_widths.png"),
    figures=Path("plots/figures"),
    fits=Path("metrics/fit"),
    ground_truth=Path("metrics/ground_truth.json"),
    comparisons=Path("metrics/comparisons.json"),
)


@stage_main
def main() -> None:
    params = load_params("learners", "data.seasons", "evaluate", "ablation", "report")
    learners = list(param(params, "learners"))
    seasons = data_seasons(params)
    evaluate = EvaluateConfig.from_params(params)
    pairs = [pair_name(a, b) for a, b in available_pairs(seasons, evaluate.pairs)]
    example_pair, note = pair_present(
        ReportConfig.from_params(params).example_pair, seasons, evaluate.pairs, "report.example_pair"
    )
    if note:
        print(f"report: {note}")
    results = load_evaluations(Path("metrics/eval"), learners, pairs, evaluations(evaluate), evaluate.metric)
    html = study_report(
        FILES,
        results,
        learners,
        seasons,
        evaluate,
        AblationConfig.from_params(params).learners,
        example_pair,
        test_images(list(example_pair)),
        pair_truths([example_pair])[example_pair],
    )
    with staged_file(Path("plots/report.html")) as tmp:
        tmp.write_text(html, encoding="utf-8")


if __name__ == "__main__":
    main()
