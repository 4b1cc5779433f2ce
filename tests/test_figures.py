"""Tests for seasonloop.reporting.figures (the figures stage's logic) and the learners' patch-normalised output."""

from __future__ import annotations

import numpy as np
from sequence_settings import sequence_config

from seasonloop.data.ground_truth import aligned_truth
from seasonloop.data.patchnorm import patch_normalise
from seasonloop.evaluation.autoencoder_descriptors import autoencoder_descriptors
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.models.core.lookup import get_learner
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.reporting.figures import AE_DESCRIPTORS, draw_figures
from tools.repository import learner_params

EVALUATE = EvaluateConfig(
    pairs=("summer-fall",),
    metric="cosine",
    extra_metrics=(),
    confidence="ratio",
    ratio_exclusion=0,
    tolerance_frames=1,
    tolerance_m=10.0,
    matchers=("single",),
)
SEQUENCE = sequence_config(v_min=0.8, v_max=1.2, v_steps=3, window=2)


class FakeAutoEncoder:
    """Code: the row means; output: the images themselves, flattened."""

    params = {"patch_size": 4}

    def __init__(self):
        self.batch_sizes = []

    def describe_code_and_output(self, images, batch_size, progress=False):
        self.batch_sizes.append(batch_size)
        return images.mean(axis=2), images.reshape(len(images), -1).astype(np.float32)

    def patchnorm_output(self, outputs, image_shape):
        return patch_normalise(outputs.reshape(len(outputs), *image_shape), 4).reshape(len(outputs), -1)


def test_autoencoder_descriptors_one_pass_per_season():
    rng = np.random.default_rng(0)
    test = {"summer": rng.random((3, 8, 8)), "fall": rng.random((3, 8, 8))}
    learner = FakeAutoEncoder()
    context = EvaluationContext(
        test,
        {},
        [],
        EVALUATE,
        SEQUENCE,
        StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05),
        7,
    )
    described = autoencoder_descriptors(learner, context)
    assert list(described) == list(AE_DESCRIPTORS) and learner.batch_sizes == [7, 7]
    for season, images in test.items():
        assert list(described["code"]) == ["summer", "fall"]
        np.testing.assert_array_equal(described["output"][season], images.reshape(3, -1).astype(np.float32))
        np.testing.assert_array_equal(
            described["output_patchnorm"][season],
            patch_normalise(described["output"][season].reshape(3, 8, 8), 4).reshape(3, -1),
        )


def test_draw_figures_without_their_learners_draws_nothing(tmp_path):
    test = {"summer": np.zeros((4, 8, 8)), "fall": np.zeros((4, 8, 8))}
    context = EvaluationContext(
        test,
        {("summer", "fall"): aligned_truth(np.arange(4), np.arange(4), 0)},
        [("summer", "fall")],
        EVALUATE,
        SEQUENCE,
        StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05),
        8,
    )
    records = draw_figures(tmp_path / "models", tmp_path, ["raw_patchnorm"], context)
    assert records.notes == [
        "no learner in learners draws Figure 2",
        "no learner in learners draws the global ICA basis",
        "no learner in learners draws Figures 12 and 13",
        "no learner in learners draws Figures 19, 19b, 19c",
    ]
    assert records.autoencoder_descriptors == {}
    assert list(tmp_path.iterdir()) == []


def test_the_global_ica_basis_figure_shows_the_mixing_columns_of_the_fitted_ica(tmp_path, monkeypatch):
    from seasonloop.reporting import figures

    rng = np.random.default_rng(0)
    images = (128 + 4 * rng.laplace(size=(300, 6)) @ rng.normal(size=(6, 8 * 16))).clip(0, 255)  # little clipped
    ica = get_learner("ica")(learner_params("ica", {"n_components": 6, "device": "cpu"}), seed=0)
    images = images.astype(np.uint8)
    ica.fit(images.reshape(300, 8, 16), progress=False)
    shown = {}
    monkeypatch.setattr(figures, "plot_image_grid", lambda rows, path, **kwargs: shown.update(rows=rows, path=path))
    figures.ica_basis_figure(ica, tmp_path / "basis.png")
    basis = np.stack([image.ravel() for row in shown["rows"] for image in row], axis=1)  # (pixels, shown)
    assert basis.shape == (8 * 16, 6) and shown["rows"][0][0].shape == (8, 16)
    # most pixel variance first, and the sources times the basis give back the centred images
    norms = np.linalg.norm(basis, axis=0)
    assert list(norms) == sorted(norms, reverse=True)
    sources = ica.estimator.transform(images.reshape(300, -1) / 255)
    order = np.argsort(-np.linalg.norm(np.linalg.pinv(ica.estimator.components_.astype(np.float64)), axis=0))
    centred = images.reshape(300, -1) / 255 - ica.estimator.mean_
    np.testing.assert_allclose(sources[:, order] @ basis.T, centred, atol=0.02)


def test_patchnorm_output_is_the_learners_output_patchnorm_descriptor():
    rng = np.random.default_rng(1)
    images = (rng.random((40, 16, 32)) * 255).astype(np.uint8)
    learner = get_learner("fae")(learner_params("fae", {"hidden": 8, "max_epochs": 1, "batch_size": 16}))
    learner.fit(images, progress=False)
    _, output = learner.describe_code_and_output(images[:6], batch_size=4)
    normalised = learner.patchnorm_output(output, images.shape[1:])
    np.testing.assert_array_equal(normalised, learner.describe_as(images[:6], "output_patchnorm", batch_size=4))
    # what the figures stage computed itself before the learner had this learner
    np.testing.assert_array_equal(
        normalised, patch_normalise(output.reshape(6, 16, 32), learner.params["patch_size"]).reshape(6, -1)
    )


def test_every_figure_a_learner_names_is_one_that_can_be_drawn():
    from seasonloop.models.core.lookup import LEARNERS, get_learner
    from seasonloop.reporting.figures import FIGURES, figure_learners

    named = {name: get_learner(name).figures for name in LEARNERS}
    assert all(set(figures) <= set(FIGURES) for figures in named.values()), named
    # each figure is some learner's (none is drawn by a name written in the figures module)
    assert {figure for figures in named.values() for figure in figures} == set(FIGURES)
    assert figure_learners(["pca", "fae", "cae", "hog"])["autoencoder"] == ["fae", "cae"]
