"""Tests for seasonloop.reporting.report: one self-contained, escaped HTML file from small hand-made inputs."""

import re

import numpy as np
import pandas as pd
import pytest
from test_results import fake_intervals

from seasonloop.data.ground_truth import aligned_truth
from seasonloop.evaluation.outcomes import COLUMNS, QueryOutcomes
from seasonloop.evaluation.records import block_records
from seasonloop.plots import plot_image_grid
from seasonloop.reporting.examples import example_grid_png, examples_section, outcome_examples
from seasonloop.reporting.html import Image, Section, Table, Text, build_report
from seasonloop.reporting.model_sections import figures_section, network_training_section, training_seasons_section
from seasonloop.reporting.sections import (
    dataset_section,
    fraction_correct_section,
    parameters_section,
    pr_section,
    runtime_section,
    similarity_section,
)
from seasonloop.reporting.summary import pr_landmarks, pr_landmarks_table

PAIRS = ["summer-fall", "winter-fall"]


@pytest.fixture
def pngs(tmp_path):
    """Two tiny PNG files written with plot_image_grid."""
    rng = np.random.default_rng(0)
    paths = [tmp_path / "a.png", tmp_path / "b.png"]
    for path in paths:
        plot_image_grid([[rng.random((8, 16))]], path)
    return paths


def metrics(fraction_correct):
    return {
        "fraction_correct": fraction_correct,
        "precision_at_full_recall": fraction_correct,
        "recall_at_1": fraction_correct,
        "recall_at_5": 0.95,
        "recall_at_10": 0.975,
        "recall_at_100_precision": 0.25,
        "auc_pr": 0.5,
        "intervals": fake_intervals(fraction_correct),
    }


def test_report_is_self_contained_and_escaped(tmp_path, pngs):
    results = {
        "pca": {"summer-fall": metrics(0.8), "winter-fall": metrics(0.1)},
        "pca+seq": {"summer-fall": metrics(0.9), "winter-fall": metrics(0.4)},
    }
    dataset = {
        "seasons": {"summer": {"frames": 1800, "train": 1510, "test": 158, "train_augmented": 3020}},
        "dropped_tunnel": 2,
        "dropped_stop": 20,
        "gap": 110,
        "detection": {"tunnel": {"found": 66, "true": 66, "precision": 1.0, "recall": 1.0}},
    }
    sections = [
        dataset_section(dataset, pngs[0]),
        fraction_correct_section(results, ["pca"], ["single", "sequence"], PAIRS, pngs[1]),
        similarity_section(pngs[0]),
        Section(
            "Odd <labels> & co",
            [Table("a <b> table", pd.DataFrame({"x<y": [1.25]}, index=["m<n"])), Text("if a < b then")],
        ),
        parameters_section("seed: 0\nname: <tag>\n"),
    ]
    page = build_report("seasonloop", sections)

    assert page.startswith("<!DOCTYPE html>") and page.count("<html") == 1
    assert page.count("data:image/png;base64,") == 3  # dataset preview, fraction correct, the similarity figure
    assert 'src="http' not in page and "<link" not in page and "<script" not in page
    assert str(tmp_path) not in page and ".png" not in page
    for heading in ["1. Dataset", "2. Fraction correct", "3. Similarity matrices", "5. Parameters"]:
        assert f"<h2>{heading}</h2>" in page
    # values: dataset counts, ours in % with its interval, the study's number for pca summer-fall (88), recall in %
    for value in ["1510", "3020", "110", "80.0 [75, 85]", "88", "90.0 [85, 95]", "97.5", "25.0", "50.0"]:
        assert f">{value}</td>" in page, value
    # the study gives no winter numbers: that pair has an "ours" column only
    assert page.count("<th>study (S)</th>") == 1  # summer-fall, single-image matching
    assert "x&lt;y" in page and "m&lt;n" in page and "a &lt;b&gt; table" in page
    assert "Odd &lt;labels&gt; &amp; co" in page and "if a &lt; b then" in page and "name: &lt;tag&gt;" in page
    assert not re.search(r"<(labels|b|tag|y|n)>", page)


def test_report_rejects_missing_and_non_png_images(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.png"):
        build_report("r", [Section("s", [Image("c", tmp_path / "missing.png")])])
    (tmp_path / "fake.png").write_text("not a png")
    with pytest.raises(ValueError, match="fake.png: not a PNG"):
        build_report("r", [Section("s", [Image("c", tmp_path / "fake.png")])])


def examples_of(distances, truth, n):
    """The examples the report shows for an evaluation of `distances`: from its per-query outcomes."""
    outcomes = QueryOutcomes.from_records(block_records(np.asarray(distances), truth, "distance", 0), truth, "distance")
    return outcome_examples(outcomes, truth, n)


def test_examples_are_the_most_confident_correct_and_wrong_matches_of_the_evaluation():
    places = np.array([10, 11, 12, 13])
    # query 0 -> 0 (correct, distance 0.1), query 1 -> 1 (correct, 0.3),
    # query 2 -> 0 (wrong, 0.05), query 3 -> 2 (wrong, 0.2)
    distances = np.array([[0.1, 0.9, 0.9, 0.9], [0.9, 0.3, 0.9, 0.9], [0.05, 0.9, 0.6, 0.9], [0.9, 0.9, 0.2, 0.7]])
    examples = examples_of(distances, aligned_truth(places, places, 0), n=1)
    assert [(e.query, e.match, e.truth, e.correct) for e in examples] == [(0, 0, 0, True), (2, 0, 2, False)]
    examples = examples_of(distances, aligned_truth(places, places, 1), n=5)
    # within one place query 3's match (place 12 for 13) counts as correct
    assert [e.query for e in examples if e.correct] == [0, 3, 1]
    assert [e.query for e in examples if not e.correct] == [2]
    outcomes = QueryOutcomes.from_records(
        block_records(distances, aligned_truth(places, places, 0), "distance", 0),
        aligned_truth(places, places, 0),
        "distance",
    )
    with pytest.raises(ValueError, match="outside the ground truth's database"):
        outcome_examples(outcomes, aligned_truth(places[1:], places, 0), n=1)
    with pytest.raises(ValueError, match="different queries"):
        outcome_examples(outcomes.take(np.arange(3)), aligned_truth(places, places, 0), n=1)


def test_examples_of_one_fold_from_the_outcomes_of_every_fold():
    """A cross-validated run's outcomes hold every fold's queries; the report's truth is one fold's."""
    rng = np.random.default_rng(0)
    folds = [np.array([0, 1, 2, 6, 7, 8]), np.array([3, 4, 5, 9, 10, 11])]
    truths = [aligned_truth(places, places, 0) for places in folds]
    outcomes = [
        QueryOutcomes.from_records(block_records(rng.random((6, 6)), truth, "distance", 0), truth, "distance")
        for truth in truths
    ]
    order = np.argsort(np.concatenate(folds))
    pooled = QueryOutcomes(**{name: np.concatenate([getattr(o, name) for o in outcomes])[order] for name in COLUMNS})
    assert outcome_examples(pooled, truths[1], 2) == outcome_examples(outcomes[1], truths[1], 2)


def test_example_grid_is_embedded():
    rng = np.random.default_rng(1)
    images = rng.integers(0, 255, size=(4, 8, 16), dtype=np.uint8)
    places = np.arange(4)
    examples = examples_of(rng.random((4, 4)), aligned_truth(places, places, 0), n=2)
    png = example_grid_png(images, images, examples, places, places, title="pca")
    page = build_report("r", [examples_section("summer-fall", {"pca": png})])
    assert page.count("data:image/png;base64,") == 1
    assert "Example matches and failures, summer-fall" in page


def test_runtime_training_and_figures_sections(pngs):
    runtime = {
        "pca": {"n_train_images": 120, "fit_seconds": 1.5, "descriptor_dimension": 100, "feature_ms_per_image": 0.25}
    }
    training = {
        "pair": "summer-fall",
        "fraction_correct": {"pca": {"summer": 0.5, "summer+winter": 0.625}},
        "intervals": {"pca": {"summer": {"low": 0.25, "high": 0.75}}},  # one only: the other is shown bare
    }
    autoencoders = {
        "fae": {
            "code": {
                "fraction_correct": {"summer-fall": 0.375},
                "interval": {"summer-fall": {"low": 0.25, "high": 0.5}},
            },
            "output_patchnorm": {
                "fraction_correct": {"summer-fall": 0.875, "winter-summer": 0.125},
                "interval": {"summer-fall": {"low": 0.75, "high": 1.0}, "winter-summer": {"low": 0.0, "high": 0.25}},
            },
        }
    }
    page = build_report(
        "r",
        [
            runtime_section(runtime),
            training_seasons_section(training, pngs[0]),
            figures_section({"fig12 patch ica filters": pngs[1]}, autoencoders, ["winter-summer", "summer-fall"]),
        ],
    )
    # runtime columns in the study's order (fit, then feature time), not the JSON's sorted order
    headers = re.findall(r"<th>([^<]+)</th>", page)
    assert [h for h in headers if h in ("fit (s)", "features (ms / image)")] == ["fit (s)", "features (ms / image)"]
    # the descriptors' pairs in the run's order, not the JSON's sorted one
    assert [h for h in headers if h.endswith(("-fall", "-summer"))] == ["winter-summer", "summer-fall"]
    for value in ["1.5", "0.25", "120", "50.0 [25, 75]", "62.5", "37.5 [25, 50]", "87.5 [75, 100]", "summer+winter"]:
        assert f">{value}</" in page, value
    assert "output_patchnorm" in page
    assert page.count("data:image/png;base64,") == 2


def test_network_training_section_shows_how_training_ended():
    training = {
        "fae": {"stop_reason": "plateau", "converged": True, "epochs_run": 57, "best_validation_loss": 0.00412},
        "cae": {"stop_reason": "max_epochs", "converged": False, "epochs_run": 3, "best_validation_loss": 0.0213},
    }
    page = build_report("r", [network_training_section(training)])
    for value in ["plateau", "max_epochs", "True", "False", "57", "0.00412", "0.0213"]:
        assert f">{value}</" in page, value
    assert "No learner that trains in epochs" in build_report("r", [network_training_section({})])


def test_sections_show_what_a_subset_run_has(pngs):
    # a run on one season skips the ablation; a run without pca, ica_bovw or an auto-encoder has no figure
    skipped = {"skipped": "skipped: it needs two seasons and data.seasons has only ['summer']"}
    adapted = {
        "pair": "winter-summer",
        "notes": ["ablation.pair summer-fall needs a season not in data.seasons: using winter-summer"],
        "fraction_correct": {"pca": {"summer": 0.5}},
    }
    page = build_report(
        "r",
        [
            training_seasons_section(skipped, pngs[0]),
            training_seasons_section(adapted, pngs[0]),
            figures_section({}, {}, ["winter-summer"]),
        ],
    )
    assert "ablation was skipped: it needs two seasons" in page
    assert "using winter-summer" in page and ">50.0</" in page
    assert "No figure: no learner in learners draws one" in page
    assert page.count("data:image/png;base64,") == 1


def test_extra_metric_rows_and_pr_landmarks_are_reported(pngs):
    results = {
        label: {"summer-fall": metrics(value), "winter-fall": metrics(value / 2)}
        for label, value in (("pca", 0.8), ("pca+seq", 0.9), ("pca@cityblock", 0.6), ("pca@cityblock+seq", 0.7))
    }
    landmarks = pr_landmarks_table(pr_landmarks(results))
    page = build_report(
        "r",
        [
            fraction_correct_section(
                results, ["pca"], ["single", "sequence"], PAIRS, pngs[1], ["cityblock"], {"cityblock": pngs[0]}
            ),
            pr_section({"summer-fall": pngs[0]}, landmarks),
        ],
    )
    assert "Fraction correct (%), single-image matching, cityblock distance" in page
    assert "Fraction correct (%), sequence matching (SeqSLAM), cityblock distance" in page
    assert "<th>pca@cityblock</th>" in page and ">60.0</td>" in page
    # the study's numbers sit beside the plain rows only: one (S) column per main-metric single table
    assert page.count("<th>study (S)</th>") == 1 + 1  # fraction correct summer-fall, PR landmarks
    assert "The study&#x27;s precision-recall landmarks beside ours" in page and ">91.0</td>" in page


def test_the_ground_truth_table_labels_each_column_by_its_key():
    # metrics/ground_truth.json comes with sorted keys; the table must not label them by position
    from seasonloop.reporting.sections import TRUTH_COLUMNS, _labelled

    record = {"summer-fall": {"mean_correct_per_query": 1.5, "n_database": 150, "n_queries": 158, "n_without_match": 3}}
    table = _labelled(pd.DataFrame.from_dict(record, orient="index"), TRUTH_COLUMNS)
    assert table.loc["summer-fall"].to_dict() == {
        "queries": 158,
        "database places": 150,
        "queries without a correct place": 3,
        "correct places per query": 1.5,
    }
