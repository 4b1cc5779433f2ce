"""The study's report: every result in one self-contained HTML page, assembled from the files the
other stages wrote.

Which files those are is the caller's (ReportFiles); this module reads them in the order the
tables list them (seasonloop.reporting.results), builds the sections (seasonloop.reporting.sections, the
example grids of seasonloop.reporting.examples) and renders the page (seasonloop.reporting.html).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from seasonloop.data.ground_truth import PairTruth
from seasonloop.io import read_json
from seasonloop.params.seasons import pair_name
from seasonloop.params.settings import EvaluateConfig
from seasonloop.reporting.comparisons import comparisons_section
from seasonloop.reporting.examples import example_grids, examples_section
from seasonloop.reporting.html import build_report
from seasonloop.reporting.model_sections import (
    cae_widths_section,
    figures_section,
    network_training_section,
    training_seasons_section,
)
from seasonloop.reporting.results import (
    EvaluationResults,
    load_autoencoder_descriptors,
    load_dataset,
    load_runtime_record,
    load_training_seasons,
)
from seasonloop.reporting.sections import (
    dataset_section,
    fraction_correct_section,
    parameters_section,
    pr_section,
    runtime_section,
    similarity_section,
    software_section,
)
from seasonloop.reporting.summary import pr_landmarks, pr_landmarks_table

TITLE = "seasonloop: loop-closure detection across seasons"
N_EXAMPLES = 3  # correct matches, and as many failures, shown per learner


@dataclass(frozen=True)
class ReportFiles:
    """Where the report's inputs are: the other stages' JSON records, descriptors and figures."""

    params: Path  # the parameter file, embedded verbatim
    dataset: Path  # seasonloop.data.datasets.dataset_record
    runtime: Path  # seasonloop.reporting.results.load_runtime, as written
    training_seasons: Path  # the training-season ablation's record
    autoencoder_descriptors: Path  # fraction correct per auto-encoder descriptor
    network_training: Path  # how each network's training ended
    outcomes: Path  # <learner>/<pair><suffix>.csv: each query's outcome and best match (the evaluate stage's)
    season_preview: Path  # a PNG
    summary: Path  # fraction_correct[@<metric>].png, pr_<pair>.png, similarity.png
    training_seasons_figure: Path  # a PNG
    cae_widths: Path  # the CAE width sweep's record (seasonloop.ablations.cae_widths)
    cae_widths_figure: Path  # a PNG
    figures: Path  # a folder of the study's other figures, *.png
    fits: Path  # <learner>.json fit records, each with the environment it was fitted in
    ground_truth: Path  # seasonloop.evaluation.pair_ground_truth.truth_record
    comparisons: Path  # the paired comparisons (seasonloop.significance.tables.run_comparisons)


def _figures(folder: Path) -> dict[str, Path]:
    """caption -> PNG of every figure in `folder` (the figures stage draws those its learners allow)."""
    if not folder.is_dir():
        raise FileNotFoundError(f"{folder}: not found (run the figures stage first)")
    return {path.stem.replace("_", " "): path for path in sorted(folder.glob("*.png"))}


def study_report(
    files: ReportFiles,
    results: EvaluationResults,
    learners: Sequence[str],
    seasons: Sequence[str],
    evaluate: EvaluateConfig,
    ablation_learners: Sequence[str],
    example_pair: tuple[str, str],
    test_images: Mapping[str, np.ndarray],
    truth: PairTruth,
) -> str:
    """The report's HTML. results: every evaluation of `learners` (seasonloop.reporting.results.load_evaluations);
    example_pair: the (database, query) seasons of the example matches, both in test_images."""
    database, query = example_pair
    pairs = results.pairs
    extra_metrics = list(evaluate.extra_metrics)
    grids = example_grids(files.outcomes, learners, database, query, test_images, truth, N_EXAMPLES)
    sections = [
        dataset_section(load_dataset(files.dataset, seasons), files.season_preview, read_json(files.ground_truth)),
        fraction_correct_section(
            results.metrics,
            learners,
            list(evaluate.matchers),
            pairs,
            files.summary / "fraction_correct.png",
            extra_metrics,
            {metric: files.summary / f"fraction_correct@{metric}.png" for metric in extra_metrics},
        ),
        pr_section(
            {pair: files.summary / f"pr_{pair}.png" for pair in pairs},
            pr_landmarks_table(pr_landmarks(results.metrics)),
        ),
        comparisons_section(read_json(files.comparisons), learners),
        similarity_section(files.summary / "similarity.png"),
        examples_section(pair_name(database, query), grids),
        runtime_section(load_runtime_record(files.runtime, learners)),
        training_seasons_section(
            load_training_seasons(files.training_seasons, ablation_learners), files.training_seasons_figure
        ),
        network_training_section(read_json(files.network_training)),
        cae_widths_section(read_json(files.cae_widths), files.cae_widths_figure),
        figures_section(
            _figures(files.figures), load_autoencoder_descriptors(files.autoencoder_descriptors, learners), pairs
        ),
        software_section({learner: read_json(files.fits / f"{learner}.json")["environment"] for learner in learners}),
        parameters_section(files.params.read_text()),
    ]
    return build_report(TITLE, sections)
