"""Tests for seasonloop.plots: every function writes a non-empty PNG."""

import numpy as np
import pandas as pd
import pytest

from seasonloop.plots import (
    plot_distance_matrix,
    plot_fraction_correct,
    plot_image_grid,
    plot_loss_curves,
    plot_pr_curves,
    plot_series,
)

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def assert_png(path):
    assert path.is_file()
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE)
    assert len(data) > 1000


def test_plot_pr_curves(tmp_path):
    path = tmp_path / "nested" / "pr.png"
    curves = {"PCA": (np.array([0.2, 0.5, 1.0]), np.array([1.0, 0.8, 0.6])), "ICA": ([0.5, 1.0], [1.0, 0.9])}
    plot_pr_curves(curves, "summer-fall", path)
    assert_png(path)
    with pytest.raises(ValueError, match="PCA"):
        plot_pr_curves({"PCA": ([0.1, 0.2], [1.0])}, "bad", tmp_path / "bad.png")


def test_plot_fraction_correct(tmp_path):
    table = pd.DataFrame({"summer-fall": [0.9, 0.85], "winter-spring": [0.2, 0.1]}, index=["PCA", "ICA"])
    reference = pd.DataFrame({"summer-fall": [0.91, 0.88], "winter-spring": [np.nan, np.nan]}, index=["ICA", "PCA"])
    path = tmp_path / "figs" / "fraction.png"
    plot_fraction_correct(table, path, reference=reference)
    assert_png(path)
    plot_fraction_correct(table, tmp_path / "plain.png", title="no reference")
    assert_png(tmp_path / "plain.png")
    with pytest.raises(ValueError, match="fractions"):
        plot_fraction_correct(table, tmp_path / "bad.png", reference=reference * 100)
    with pytest.raises(ValueError, match="same methods"):
        plot_fraction_correct(table, tmp_path / "bad.png", reference=reference.iloc[:1])


def test_the_fraction_correct_figure_fits_a_page_with_every_learner_and_pair(tmp_path):
    from PIL import Image

    learners = ["raw_patchnorm", "pca", "pca_whiten", "ica", "ica_bovw", "fae", "cae"]
    labels = [*learners, *(f"{learner}+seq" for learner in learners)]
    pairs = ["summer-fall", "summer-spring", "spring-fall", "winter-summer", "winter-fall", "winter-spring"]
    table = pd.DataFrame(np.linspace(0.05, 0.95, len(labels) * len(pairs)).reshape(len(labels), -1), labels, pairs)
    path = tmp_path / "fraction.png"
    plot_fraction_correct(table, path)
    width, height = Image.open(path).size
    assert width <= 1600 and height <= 1200


def test_plot_distance_matrix_downsamples_large(tmp_path):
    rng = np.random.default_rng(0)
    distances = rng.random((1300, 1100)).astype(np.float32)
    distances[np.arange(1100), np.arange(1100)] = 0.0
    distances[0, :5] = np.inf  # sequence scores can be infinite
    path = tmp_path / "matrix.png"
    plot_distance_matrix(distances, "summer-fall", path)
    assert_png(path)


def test_plot_image_grid(tmp_path):
    rng = np.random.default_rng(1)
    images = [[rng.random((32, 64)) for _ in range(3)], [rng.random((32, 64)) * 255, np.zeros((32, 64))]]
    path = tmp_path / "grid.png"
    plot_image_grid(images, path, row_labels=["a", "b"], col_labels=["x", "y", "z"], title="grid")
    assert_png(path)
    with pytest.raises(ValueError, match="col_labels"):
        plot_image_grid(images, tmp_path / "bad.png", col_labels=["x"])
    with pytest.raises(ValueError, match=r"images\[0\]\[0\]"):
        plot_image_grid([[np.zeros((2, 2, 2))]], tmp_path / "bad.png")


def test_plot_series(tmp_path):
    series = {
        "PCA": (["S", "S+W", "S+W+Sp", "all"], [0.8, 0.82, 0.85, 0.86]),
        "ICA": (["S", "S+W", "S+W+Sp", "all"], [0.85, 0.86, 0.88, 0.9]),
    }
    path = tmp_path / "series.png"
    plot_series(series, path, "training seasons", "training set", "fraction correct")
    assert_png(path)
    with pytest.raises(ValueError, match="ICA"):
        plot_series({"ICA": (["a", "b"], [1.0])}, tmp_path / "bad.png", "t", "x", "y")


def test_plot_loss_curves(tmp_path):
    curves = {
        "fae": {"train": [0.04, 0.02, 0.015], "validation": [0.05, 0.03, 0.031]},
        "cae": {"train": [0.06], "validation": [0.07]},
    }
    plot_loss_curves(curves, tmp_path / "loss.png", title="loss")
    assert_png(tmp_path / "loss.png")
    with pytest.raises(ValueError, match="empty"):
        plot_loss_curves({}, tmp_path / "none.png", title="loss")
