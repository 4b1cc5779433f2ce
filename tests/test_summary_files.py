"""Tests for seasonloop.reporting.summary_files: the summary's record, tables, figures and dvc plots tables."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

# the fake metrics/eval and plots/pr folders of test_results
from test_results import METHODS, PAIRS, VARIANTS, write_evaluations

from seasonloop.reporting.results import load_evaluations
from seasonloop.reporting.summary_files import (
    compare_record,
    summary_record,
    write_dvc_plots,
    write_summary_files,
    write_tables,
)

RUNTIME = {
    "pca": {"fit_seconds": 1.23456, "n_train_images": 100, "feature_ms_per_image": 0.5, "descriptor_dimension": 16},
    "ica": {"fit_seconds": 20.0, "n_train_images": 100, "feature_ms_per_image": 1.0, "descriptor_dimension": 16},
}


@pytest.fixture
def results(tmp_path):
    inputs = tmp_path / "inputs"
    write_evaluations(inputs / "eval", inputs / "pr")
    return load_evaluations(inputs / "eval", METHODS, PAIRS, VARIANTS, "cosine", pr_dir=inputs / "pr")


def training_curves() -> pd.DataFrame:
    return pd.DataFrame(
        {
            "learner": ["fae"] * 3,
            "metric": ["loss/train", "loss/validation", "lr"],
            "step": [1, 1, 1],
            "value": [0.5, 0.25, 0.001],
        }
    )


def test_summary_record(results):
    record = summary_record(results)
    assert list(record) == ["fraction_correct", "fraction_correct_interval", "mean_fraction_correct", "pr_landmarks"]
    assert list(record["fraction_correct"]) == results.labels
    assert record["fraction_correct"]["ica"] == {"summer-fall": 0.1, "winter-fall": 0.11}
    assert record["fraction_correct_interval"]["ica"]["summer-fall"] == pytest.approx({"low": 0.05, "high": 0.15})
    assert record["mean_fraction_correct"]["ica"] == pytest.approx(0.105)
    assert isinstance(record["mean_fraction_correct"]["ica"], float)
    # the study's landmarks for summer-fall pca and ica, ours beside them
    assert record["pr_landmarks"]["summer-fall"]["pca"]["recall_at_100_precision"] == {"ours": 0.5, "study": 0.67}


def test_the_compared_metrics_are_the_main_distance_averaged_over_pairs(results):
    record = compare_record(results)
    assert list(record) == [label for label in results.labels if "@" not in label]
    assert record["ica"] == pytest.approx(0.105)


def test_write_summary_files(tmp_path, results):
    out = tmp_path / "summary"
    out.mkdir()
    write_summary_files(out, results, RUNTIME, training_curves())
    names = sorted(path.relative_to(out).as_posix() for path in out.rglob("*") if path.is_file())
    assert names == [
        "fraction_correct.csv",
        "fraction_correct.md",
        "fraction_correct.png",
        "fraction_correct@cityblock.png",
        "pr/summer-fall.csv",
        "pr/winter-fall.csv",
        "pr_landmarks.md",
        "pr_summer-fall.png",
        "pr_winter-fall.png",
        "runtime.md",
        "training_loss.csv",
    ]
    assert (out / "fraction_correct.png").read_bytes().startswith(b"\x89PNG")


def test_tables_text(tmp_path, results):
    write_tables(tmp_path, results, RUNTIME)
    markdown = (tmp_path / "fraction_correct.md").read_text()
    assert markdown.startswith(
        "Fraction of correct matches (%), ours with its 95% block-bootstrap interval in square brackets "
        "(the study's in round brackets where it gives one)\n\n"
        "| method | summer-fall | winter-fall |\n|---|---|---|\n"
    )
    # ours with its interval, then the study's number in brackets where it gives one
    assert "| pca | 0.0 [0, 5] (88) | 1.0 [0, 6] |\n" in markdown
    assert "| ica@cityblock | 10.2 [5, 15] | 11.2 [6, 16] |\n" in markdown
    csv = (tmp_path / "fraction_correct.csv").read_text().splitlines()
    assert csv[0] == "method,pair,fraction_correct,label" and csv[1] == "pca,summer-fall,0.000,summer-fall pca"
    landmarks = (tmp_path / "pr_landmarks.md").read_text()
    assert "| summer-fall pca recall at 100% precision | 50.0 | 67.0 |" in landmarks
    runtime = (tmp_path / "runtime.md").read_text()
    assert "| pca | 1.235 | 100 | 0.5 | 16 |" in runtime


def test_dvc_plots_tables(tmp_path, results):
    write_dvc_plots(tmp_path, results, training_curves())
    pr = pd.read_csv(tmp_path / "pr" / "summer-fall.csv")
    assert list(pr.columns) == ["learner", "recall", "precision"]
    assert pr["learner"].drop_duplicates().tolist() == ["pca", "ica", "pca+seq", "ica+seq"]
    losses = pd.read_csv(tmp_path / "training_loss.csv")
    assert losses["metric"].tolist() == ["loss/train", "loss/validation"]
    np.testing.assert_allclose(losses["value"], [0.5, 0.25])
