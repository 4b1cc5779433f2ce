"""Picard-O (TorchPicard), the python-picard reference it must equal, and the stationarity measure
that every ICA solver reports."""

import numpy as np
import pytest
import torch
from ica_data import estimator, images, mixed_sources

from seasonloop.models.core.fastica import TorchFastICA
from seasonloop.models.core.ica_stationarity import amari_distance, relative_gradient
from seasonloop.models.core.learner import RUN_KEYS
from seasonloop.models.core.lookup import get_learner, load_learner
from seasonloop.models.core.picard import LibraryPicard, TorchPicard
from tools.repository import learner_params

N_SUPER, N_SUB, N_FEATURES, N_SAMPLES = 5, 3, 16, 5000
N_SOURCES = N_SUPER + N_SUB


@pytest.fixture(scope="module")
def mixture() -> tuple[np.ndarray, np.ndarray]:
    """Laplace and uniform sources mixed into more features: (data, mixing) (ica_data.mixed_sources)."""
    return mixed_sources(N_SAMPLES, N_FEATURES, N_SUPER, N_SUB)


@pytest.mark.parametrize("precision", ["float32", "float64"])
def test_recovers_super_and_sub_gaussian_sources_to_the_gradient_tolerance(mixture, precision):
    data, mixing = mixture
    ica = estimator(TorchPicard, N_SOURCES, max_iter=500, tol=1e-7, seed=0, precision=precision).fit(data)
    assert ica.converged_ and ica.n_iter_ < 500
    # its own criterion is the shared measure, confirmed on sources computed afresh from W
    assert ica.criterion_ < 1e-7 and ica.gradient_ < 1e-7
    assert amari_distance(ica.components_, mixing) < 0.03
    sources = ica.transform(data)
    assert sources.dtype == np.float32 and sources.shape == (N_SAMPLES, N_SOURCES)
    np.testing.assert_allclose(np.cov(sources, rowvar=False, bias=True), np.eye(N_SOURCES), atol=1e-3)


def test_equals_python_picard_from_the_same_start(mixture):
    """The same whitened data and initial matrix: python-picard and ours take the same steps."""
    data, _ = mixture
    ours = estimator(TorchPicard, N_SOURCES, max_iter=500, tol=1e-8, seed=3, precision="float64").fit(data)
    reference = estimator(LibraryPicard, N_SOURCES, max_iter=500, tol=1e-8, seed=3, precision="float64").fit(data)
    assert reference.converged_ and ours.converged_
    # ours may spend one more gradient evaluation confirming the result on fresh sources
    assert reference.n_iter_ <= ours.n_iter_ <= reference.n_iter_ + 1
    np.testing.assert_allclose(ours.components_, reference.components_, atol=1e-5)


def test_relative_gradient_is_zero_at_fastica_fixed_points_and_not_elsewhere(mixture):
    data, _ = mixture
    fastica = estimator(TorchFastICA, N_SOURCES, max_iter=1000, tol=1e-7, seed=0, precision="float64").fit(data)
    assert fastica.converged_
    at_fixed_point = relative_gradient(fastica.transform(data))
    assert at_fixed_point < 1e-5
    np.testing.assert_allclose(at_fixed_point, fastica.gradient_, rtol=0.2, atol=1e-6)
    # a small rotation of the same sources (still white) is not stationary
    angle = 0.1
    rotation = np.eye(N_SOURCES)
    rotation[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
    assert relative_gradient(fastica.transform(data) @ rotation) > 100 * at_fixed_point
    # scale and mean do not matter: the sources are standardised first
    assert relative_gradient(3.0 * fastica.transform(data) + 5.0) == pytest.approx(at_fixed_point, rel=1e-2)


def test_a_stopped_fit_says_so_and_a_seed_fixes_the_result(mixture):
    data, _ = mixture
    stopped = estimator(TorchPicard, N_SOURCES, max_iter=2, tol=1e-7, seed=0).fit(data)
    assert stopped.converged_ is False and stopped.n_iter_ == 2 and stopped.criterion_ >= 1e-7
    first, second = (estimator(TorchPicard, N_SOURCES, seed=7, tol=1e-7, max_iter=500).fit(data) for _ in range(2))
    for key, value in first.to_arrays().items():
        np.testing.assert_array_equal(second.to_arrays()[key], value)


class StopsEarlyOnce(TorchPicard):
    """TorchPicard whose first run stops at 1e-3 and calls it met, as an iterate does whose stored
    model misses tol by the float32 rounding of its sources (here by far more)."""

    def _rotate(self, whitened, unmixing, progress, tol, max_iter):
        self.aims = [*getattr(self, "aims", []), (tol, max_iter)]
        if len(self.aims) == 1:
            rotated = super()._rotate(whitened, unmixing, progress, 1e-3, max_iter)
            self.converged_ = True
            return rotated
        return super()._rotate(whitened, unmixing, progress, tol, max_iter)


def test_a_stored_model_that_misses_tol_goes_on_from_where_it_stopped(mixture):
    data, _ = mixture
    ica = estimator(StopsEarlyOnce, N_SOURCES, max_iter=500, tol=1e-7, seed=0, precision="float64").fit(data)
    first_run = estimator(TorchPicard, N_SOURCES, max_iter=500, tol=1e-3, seed=0, precision="float64").fit(data)
    assert first_run.gradient_ > 1e-7  # the first stop left the stored model above tol
    # then on from that unmixing, aiming at a tenth of tol, with what was left of the budget
    assert ica.aims == [(1e-7, 500), (1e-8, 500 - first_run.n_iter_)]
    assert ica.converged_ and ica.gradient_ < 1e-7 and ica.n_iter_ > first_run.n_iter_


def test_progress_bar_shows_the_gradient(mixture, capsys):
    data, _ = mixture
    estimator(TorchPicard, N_SOURCES, max_iter=5, seed=0).fit(data, progress=True)
    bar = capsys.readouterr().err
    assert "Picard-O iterations" in bar and "gradient=" in bar


@pytest.mark.parametrize("fun", ["logcosh", "exp", "cube"])
def test_python_picard_optimises_the_same_density_as_ours(fun):
    """python-picard's fun="exp" is Exp(alpha=0.1) while ours (and scikit-learn's) has alpha 1: given
    as density objects, both optimise one contrast and reach one unmixing."""
    rng = np.random.default_rng(0)
    data = rng.laplace(size=(2000, 32)) @ rng.normal(size=(32, 32))
    ours = estimator(TorchPicard, 32, max_iter=500, tol=1e-7, seed=0, precision="float64", fun=fun).fit(data)
    reference = estimator(LibraryPicard, 32, max_iter=500, tol=1e-7, seed=0, precision="float64", fun=fun).fit(data)
    assert ours.converged_ and reference.converged_
    np.testing.assert_allclose(ours.components_, reference.components_, atol=1e-4)


@pytest.mark.parametrize("solver", [TorchPicard, TorchFastICA, LibraryPicard])
def test_every_solver_traces_the_gradient_of_each_iterate(mixture, solver):
    """trace_[i] is the gradient of the unmixing after i iterations (timed from the fit's start,
    whitening included): the model a fit of max_iter i returns has that gradient."""
    data, _ = mixture
    traced = estimator(solver, N_SOURCES, max_iter=4, tol=1e-12, seed=0, precision="float64").fit(data)
    times = [seconds for seconds, _ in traced.trace_]
    assert len(traced.trace_) == 4 and times == sorted(times) and times[0] > 0
    for iterations in (1, 2, 3):
        stopped = estimator(solver, N_SOURCES, max_iter=iterations, tol=1e-12, seed=0, precision="float64").fit(data)
        assert traced.trace_[iterations][1] == pytest.approx(stopped.gradient_, rel=1e-3)


def test_ica_learner_with_picard_in_float32_records_the_shared_measure(tmp_path):
    train, test = images(600, 0), images(50, 1)
    changes = {"n_components": 8, "device": "cpu", "solver": "picard", "precision": "float32"}
    learner = get_learner("ica")(learner_params("ica", changes), seed=2)
    info = learner.fit(train, progress=False)
    assert info["solver"] == "picard" and info["precision"] == "float32"
    assert info["converged"] is True and info["gradient"] < info["tol"] == 1e-7
    assert info["own_criterion"] == {
        "name": "gradient",
        "value": info["own_criterion"]["value"],
        "tol": 1e-7,
        "met": True,
    }
    learner.save(tmp_path)
    loaded = load_learner(tmp_path)
    assert loaded.fit_info == learner.fit_info == {key: value for key, value in info.items() if key not in RUN_KEYS}
    np.testing.assert_array_equal(loaded.describe(test), learner.describe(test))
    # every solver reports converged by the same measure: FastICA meets its own test long before
    fastica = get_learner("ica")(
        learner_params("ica", {"n_components": 8, "device": "cpu", "solver": "fastica"}), seed=2
    )
    record = fastica.fit(train, progress=False)
    assert record["own_criterion"]["name"] == "change" and record["own_criterion"]["met"] is True
    assert record["converged"] == (record["gradient"] < 1e-7)
    assert bool(record["convergence_warnings"]) == (not record["converged"])
    # judged on the stored model: the gradient of the sources its descriptors are, nothing else
    for fitted, fit_record in ((fastica, record), (learner, info)):
        assert fit_record["gradient"] == pytest.approx(relative_gradient(fitted.describe(train)), rel=1e-6)


@pytest.mark.skipif(not torch.cuda.is_available(), reason="no CUDA device")
def test_cuda_matches_cpu(mixture):
    data, mixing = mixture
    cpu = estimator(TorchPicard, N_SOURCES, seed=0, tol=1e-7, max_iter=500, device="cpu").fit(data)
    cuda = estimator(TorchPicard, N_SOURCES, seed=0, tol=1e-7, max_iter=500, device="cuda").fit(data)
    assert cuda.converged_ and amari_distance(cuda.components_, mixing) < 0.03
    np.testing.assert_allclose(cuda.transform(data), cpu.transform(data), atol=2e-3)
