"""Tests for seasonloop.reporting.report.study_report: the whole report assembled from result files in tmp_path."""

from __future__ import annotations

import shutil
from dataclasses import asdict

import numpy as np
import pytest

# the fake metrics/eval folder of test_results
from test_results import LEARNERS, PAIRS, VARIANTS, write_evaluations

from seasonloop.data.datasets import trained_on
from seasonloop.data.ground_truth import aligned_truth
from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.evaluation.records import block_records
from seasonloop.io import write_json
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.plots import plot_image_grid
from seasonloop.reporting.report import ReportFiles, study_report
from seasonloop.reporting.results import load_evaluations
from seasonloop.significance.tables import comparison_tables, pair_comparisons

# the main metric, both matchers: the first two of VARIANTS
TRUTH = aligned_truth(np.arange(5), np.arange(5), 0)
EVALUATE = EvaluateConfig(
    pairs=tuple(PAIRS),
    metric="cosine",
    extra_metrics=(),
    confidence="ratio",
    ratio_exclusion=0,
    tolerance_frames=0,
    tolerance_m=10.0,
    matchers=("single", "sequence"),
)
SEASONS = ["summer", "winter", "fall"]
# what the fit records say a learner was trained on: fitted by another run (stages/fit.py's
# fitted_elsewhere), and fitted here on the training places of one season
TRAINED_ON = {
    "pca": "elsewhere: /runs/other/models/pca (not this dataset; its own params)",
    "ica": trained_on(True, ["summer"], whole_route=False),
}


def report_files(root) -> ReportFiles:
    """Every input of the report under root, the smallest that builds."""
    png = root / "one.png"
    plot_image_grid([[np.random.default_rng(0).random((4, 8))]], png)
    files = ReportFiles(
        params=root / "params.yaml",
        dataset=root / "dataset.json",
        runtime=root / "runtime.json",
        training_seasons=root / "training.json",
        autoencoder_descriptors=root / "ae.json",
        network_training=root / "network_training.json",
        outcomes=root / "outcomes",
        season_preview=png,
        summary=root / "summary",
        training_seasons_figure=png,
        cae_widths=root / "cae_widths.json",
        cae_widths_figure=png,
        figures=root / "figures",
        fits=root / "fit",
        ground_truth=root / "ground_truth.json",
        comparisons=root / "comparisons.json",
    )
    write_json(files.comparisons, fake_comparisons())
    write_json(
        files.ground_truth,
        {
            "kind": "aligned",
            "correct": "the query's own frame index +- 0 places",
            "pairs": {
                "summer-fall": {"n_queries": 5, "n_database": 5, "n_without_match": 0, "mean_correct_per_query": 1.0}
            },
        },
    )
    files.params.write_text("seed: 0\n")
    write_json(
        files.dataset,
        {
            "seasons": {
                season: {"frames": 10, "train": 6, "test": 3, "train_augmented": 12} for season in reversed(SEASONS)
            },
            "dropped_tunnel": 1,
            "dropped_stop": 0,
            "gap": 2,
        },
    )
    write_json(
        files.runtime,
        {
            learner: {
                "fit_seconds": 1.0,
                "n_train_images": 6,
                "feature_ms_per_image": 0.5,
                "descriptor_dimension": 4,
                "trained_on": TRAINED_ON[learner],
            }
            for learner in LEARNERS
        },
    )
    write_json(files.training_seasons, {"skipped": "skipped: a test"})
    write_json(files.autoencoder_descriptors, {})
    write_json(files.network_training, {})
    width = {
        "width": 0.0625,
        "channels": [6, 16, 24],
        "converged": True,
        "stop_reason": "plateau",
        "epochs_run": 30,
        "best_validation_loss": 0.003,
        "cosine_with_input": 0.9,
        **{
            descriptor: {"fraction_correct": {"summer-fall": 0.5}, "agreement_with_raw": {"summer-fall": 0.75}}
            for descriptor in ("output_patchnorm", "code")
        },
    }
    write_json(
        files.cae_widths,
        {
            "pairs": ["summer-fall"],
            "metric": "cosine",
            "widths": {"1/16": width},
            "raw_patchnorm": {"fraction_correct": {"summer-fall": 0.25}},
        },
    )
    rng = np.random.default_rng(1)
    for learner in LEARNERS:
        # the example pair's single-image outcomes, as the evaluate stage writes them
        records = block_records(rng.random((5, 5)), TRUTH, EVALUATE.confidence, 0)
        (files.outcomes / learner).mkdir(parents=True)
        QueryOutcomes.from_records(records, TRUTH, EVALUATE.confidence).to_csv(
            files.outcomes / learner / "summer-fall.csv"
        )
    files.summary.mkdir()
    for name in ["fraction_correct", "similarity", *(f"pr_{pair}" for pair in PAIRS)]:
        shutil.copy(png, files.summary / f"{name}.png")
    for learner in LEARNERS:
        write_json(files.fits / f"{learner}.json", {"environment": {"numpy": "2.4.6", "torch_threads": 2}})
    files.figures.mkdir()
    shutil.copy(png, files.figures / "fig02_pca_projection.png")
    return files


def fake_comparisons() -> dict:
    """A comparisons record of the fake run's labels, computed by the library from random outcomes."""
    settings = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)
    rng = np.random.default_rng(5)
    correct = {learner + suffix: rng.random(5) < 0.5 for learner in LEARNERS for _, _, suffix in VARIANTS}
    tables = comparison_tables(LEARNERS, VARIANTS)
    pairs = {pair: pair_comparisons(lambda label: (np.arange(5), correct[label]), tables, settings) for pair in PAIRS}
    return {"statistics": asdict(settings), "order": {"pairs": PAIRS, "tables": list(tables)}, "pairs": pairs}


def test_study_report_from_files(tmp_path):
    write_evaluations(tmp_path / "eval", tmp_path / "pr")
    results = load_evaluations(tmp_path / "eval", LEARNERS, PAIRS, VARIANTS[:2], "cosine")
    files = report_files(tmp_path)
    images = {season: np.random.default_rng(2).random((5, 4, 8)) for season in SEASONS}
    page = study_report(files, results, LEARNERS, SEASONS, EVALUATE, ["pca"], ("summer", "fall"), images, TRUTH)
    assert page.startswith("<!DOCTYPE html>") and "seasonloop: loop-closure detection across seasons" in page
    assert "Ground truth (aligned): a match is correct when it is the query&#x27;s own frame index" in page
    titles = [
        "Dataset",
        "Fraction correct",
        "Precision-recall curves",
        "Paired comparisons",
        "Similarity matrices",
        "Example matches and failures, summer-fall",
        "Runtimes",
        "Training-season effect",
        "Network training",
        "CAE width",
        "The study&#x27;s other figures",
        "Software",
        "Parameters",
    ]
    for number, title in enumerate(titles, 1):
        assert f"<h2>{number}. {title}</h2>" in page, title
    # the seasons in the run's order, not the JSON's sorted one
    assert page.index("<th>summer</th>") < page.index("<th>winter</th>") < page.index("<th>fall</th>")
    assert "The training-season ablation was skipped: a test." in page and "fig02 pca projection" in page
    assert "seed: 0" in page and str(tmp_path) not in page
    # the runtime table says what each learner was trained on, a learner fitted elsewhere included
    assert "<th>trained on</th>" in page and all(trained_on in page for trained_on in TRAINED_ON.values())
    assert "<td>6/16/24</td>" in page and "<th>1/16</th>" in page
    # every fraction correct with its interval (pca on summer-fall: 0 [0, 5]); the paired tables
    assert "<td>0.0 [0, 5]</td>" in page
    assert "summer-fall: learner against learner" in page and "pca+seq vs pca" in page


def test_study_report_needs_the_figures_folder(tmp_path):
    write_evaluations(tmp_path / "eval", tmp_path / "pr")
    results = load_evaluations(tmp_path / "eval", LEARNERS, PAIRS, VARIANTS[:2], "cosine")
    files = report_files(tmp_path)
    shutil.rmtree(files.figures)
    images = {season: np.zeros((5, 4, 8)) for season in SEASONS}
    with pytest.raises(FileNotFoundError, match="run the figures stage first"):
        study_report(files, results, LEARNERS, SEASONS, EVALUATE, ["pca"], ("summer", "fall"), images, TRUTH)


def test_a_table_without_the_studys_numbers_keeps_the_learners_names():
    import pandas as pd

    from seasonloop.reporting.sections import _beside_study

    ours = pd.DataFrame({"winter-fall": [20.9, 22.2]}, index=["raw_patchnorm", "pca"])
    study = pd.DataFrame({"winter-fall": [np.nan, np.nan]}, index=["raw_patchnorm", "pca"])
    bounds = (ours - 5, ours + 5)
    table = _beside_study(ours, study, bounds)
    assert list(table.index) == ["raw_patchnorm", "pca"]
    assert table.loc["pca", ("winter-fall", "ours")] == "22.2 [17, 27]"
