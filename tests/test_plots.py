"""Tests for seasonloop.plots and the summary's fraction-correct figure: every function writes a non-empty PNG."""

import numpy as np
import pandas as pd
import pytest
from PIL import Image

from seasonloop.evaluation.blocks import similarity_thumbnail
from seasonloop.plots import plot_image_grid, plot_loss_curves, plot_pr_curves, plot_series, plot_similarity_grid
from seasonloop.reporting.fraction_plots import plot_fraction_correct

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
    with pytest.raises(ValueError, match="same learners"):
        plot_fraction_correct(table, tmp_path / "bad.png", reference=reference.iloc[:1])
    # error bars: drawn where an interval is given, refused in percent
    low, high = table - 0.05, (table + 0.05).clip(upper=1.0)
    plot_fraction_correct(table, tmp_path / "bars.png", title="no reference", intervals=(low, high))
    assert Image.open(tmp_path / "bars.png").tobytes() != Image.open(tmp_path / "plain.png").tobytes()
    with pytest.raises(ValueError, match="intervals must hold fractions"):
        plot_fraction_correct(table, tmp_path / "bad.png", intervals=(low * 100, high * 100))


def test_the_fraction_correct_figure_fits_a_page_with_every_learner_and_pair(tmp_path):

    learners = ["raw_patchnorm", "pca", "pca_whiten", "ica", "ica_bovw", "fae", "cae"]
    labels = [*learners, *(f"{learner}+seq" for learner in learners)]
    pairs = ["summer-fall", "summer-spring", "spring-fall", "winter-summer", "winter-fall", "winter-spring"]
    table = pd.DataFrame(np.linspace(0.05, 0.95, len(labels) * len(pairs)).reshape(len(labels), -1), labels, pairs)
    path = tmp_path / "fraction.png"
    plot_fraction_correct(table, path)
    width, height = Image.open(path).size
    assert width <= 1600 and height <= 1200


def test_similarity_thumbnails_downsample_keep_the_matches_and_blank_the_infinite():
    rng = np.random.default_rng(0)
    distances = 1.0 + rng.random((1300, 1100))
    distances[np.arange(1100), np.arange(1100)] = 0.0
    distances[:9, :] = np.inf  # sequence scores can be infinite: the first block of 9 rows
    thumbnail = similarity_thumbnail(distances)
    assert thumbnail.shape == (145, 158) and thumbnail.dtype == np.float16  # blocks of 9 rows, 7 columns
    assert np.isnan(thumbnail[0]).all() and np.nanmin(thumbnail) >= 0.0
    # a block holding a true match keeps its minimum distance: each row of blocks that holds part
    # of the diagonal shows it as the most similar cell
    assert (np.nanmax(thumbnail[1:123], axis=1) == 1.0).all()


def test_the_similarity_grid_reads_at_a_laptops_width(tmp_path):
    rng = np.random.default_rng(1)
    learners = ["raw_patchnorm", "pca", "pca_whiten", "ica", "ica_bovw", "fae", "cae"]
    pairs = ["summer-fall", "summer-spring", "spring-fall", "winter-summer", "winter-fall", "winter-spring"]
    thumbnails = {learner: {pair: rng.random((158, 158)).astype(np.float16) for pair in pairs} for learner in learners}
    path = tmp_path / "similarity.png"
    plot_similarity_grid(thumbnails, path, "Similarity")
    assert_png(path)
    width, height = Image.open(path).size
    assert width <= 1366 and height <= 1700, (width, height)
    with pytest.raises(ValueError, match="expected"):
        plot_similarity_grid({"a": {"x": thumbnails["pca"]["summer-fall"]}, "b": {}}, path, "Similarity")


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
