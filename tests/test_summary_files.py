"""Tests for seasonloop.reporting.summary_files: the summary's record, tables, figures and dvc plots tables."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

# the fake metrics/eval and plots/pr folders of test_results
from test_results import LEARNERS, PAIRS, VARIANTS, write_evaluations

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.reporting.results import load_evaluations
from seasonloop.reporting.summary_files import (
    compare_record,
    mean_intervals,
    summary_record,
    write_dvc_plots,
    write_summary_files,
    write_tables,
)
from seasonloop.significance.means import mean_interval

SETTINGS = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)

RUNTIME = {
    "pca": {"fit_seconds": 1.23456, "n_train_images": 100, "feature_ms_per_image": 0.5, "descriptor_dimension": 16},
    "ica": {"fit_seconds": 20.0, "n_train_images": 100, "feature_ms_per_image": 1.0, "descriptor_dimension": 16},
}


@pytest.fixture
def results(tmp_path):
    inputs = tmp_path / "inputs"
    write_evaluations(inputs / "eval", inputs / "pr")
    return load_evaluations(inputs / "eval", LEARNERS, PAIRS, VARIANTS, "cosine", pr_dir=inputs / "pr")


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
    record = summary_record(results, {label: {"low": 0.0, "high": 0.5} for label in results.labels})
    assert list(record) == [
        "fraction_correct",
        "fraction_correct_interval",
        "mean_fraction_correct",
        "mean_fraction_correct_interval",
        "pr_landmarks",
    ]
    assert list(record["mean_fraction_correct_interval"]) == results.labels
    assert record["mean_fraction_correct_interval"]["ica"] == {"low": 0.0, "high": 0.5}
    assert list(record["fraction_correct"]) == results.labels
    assert record["fraction_correct"]["ica"] == {"summer-fall": 0.1, "winter-fall": 0.11}
    assert record["fraction_correct_interval"]["ica"]["summer-fall"] == pytest.approx({"low": 0.05, "high": 0.15})
    assert record["mean_fraction_correct"]["ica"] == pytest.approx(0.105)
    assert isinstance(record["mean_fraction_correct"]["ica"], float)
    # the study's landmarks for summer-fall pca and ica, ours beside them
    assert record["pr_landmarks"]["summer-fall"]["pca"]["recall_at_100_precision"] == {"ours": 0.5, "study": 0.67}


def test_mean_intervals_are_of_the_outcomes_of_every_label(tmp_path):
    rng = np.random.default_rng(0)
    written: dict[str, list[np.ndarray]] = {}
    for learner in LEARNERS:
        for _, _, suffix in VARIANTS:
            for pair in PAIRS:
                correct = rng.random(60) < 0.5
                written.setdefault(learner + suffix, []).append(correct)
                (tmp_path / learner).mkdir(exist_ok=True)
                n = len(correct)
                QueryOutcomes(
                    np.arange(n), correct, rng.random(n), np.ones(n, bool), correct, np.arange(n), np.zeros(n)
                ).to_csv(tmp_path / learner / f"{pair}{suffix}.csv")
    intervals = mean_intervals(tmp_path, LEARNERS, VARIANTS, PAIRS, SETTINGS)
    assert set(intervals) == set(written)
    for label, by_pair in written.items():
        assert intervals[label] == mean_interval(by_pair, [np.arange(60)] * len(by_pair), SETTINGS)
        assert intervals[label]["low"] <= np.mean([c.mean() for c in by_pair]) <= intervals[label]["high"]
    (tmp_path / LEARNERS[0] / f"{PAIRS[0]}.csv").unlink()
    with pytest.raises(ValueError, match=f"{PAIRS[0]}.csv"):
        mean_intervals(tmp_path, LEARNERS, VARIANTS, PAIRS, SETTINGS)


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
        "Fraction of correct matches (%), ours with its 95% interval along the route in square brackets "
        "(the study's in round brackets where it gives one; [not enough queries]: too few for an interval, "
        "or for the length of the runs of the learner's outcomes, as metrics/eval's reason says)\n\n"
        "| learner | summer-fall | winter-fall |\n|---|---|---|\n"
    )
    # ours with its interval, then the study's number in brackets where it gives one
    assert "| pca | 0.0 [0, 5] (88) | 1.0 [0, 6] |\n" in markdown
    assert "| ica@cityblock | 10.2 [5, 15] | 11.2 [6, 16] |\n" in markdown
    csv = (tmp_path / "fraction_correct.csv").read_text().splitlines()
    assert csv[0] == "learner,pair,fraction_correct,label" and csv[1] == "pca,summer-fall,0.000,summer-fall pca"
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
