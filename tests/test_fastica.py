import numpy as np
import pytest
import torch
from ica_data import estimator, images, mixed_sources
from sklearn.decomposition import FastICA

from seasonloop.models.core.fastica import TorchFastICA
from seasonloop.models.core.ica_stationarity import amari_distance
from seasonloop.models.core.learner import RUN_KEYS, to_float
from seasonloop.models.core.lookup import get_learner, load_learner
from seasonloop.models.core.torch_ica import WHITEN_SOLVERS
from seasonloop.models.ica import ICA_SOLVERS
from tools.repository import learner_params

N_SOURCES, N_FEATURES, N_SAMPLES = 6, 16, 4000


@pytest.fixture(scope="module")
def mixture() -> tuple[np.ndarray, np.ndarray]:
    """Laplace sources mixed into more features: (data, mixing) (ica_data.mixed_sources)."""
    return mixed_sources(N_SAMPLES, N_FEATURES, N_SOURCES)


def test_amari_distance_is_zero_for_a_scaled_permutation_only():
    mixing = np.random.default_rng(1).normal(size=(5, 5))
    permuted_scaled = np.diag([2.0, -1.0, 0.5, 3.0, 1.0])[[2, 0, 1, 4, 3]] @ np.linalg.inv(mixing)
    assert amari_distance(permuted_scaled, mixing) < 1e-12
    assert amari_distance(np.ones((5, 5)), np.eye(5)) == pytest.approx(1.0)


def test_recovers_known_sources(mixture):
    data, mixing = mixture
    ica = estimator(TorchFastICA, N_SOURCES, max_iter=200, tol=1e-4, seed=0).fit(data)
    assert ica.converged_ and ica.n_iter_ < 200
    assert amari_distance(ica.components_, mixing) < 0.03
    sources = ica.transform(data)
    assert sources.dtype == np.float32 and sources.shape == (N_SAMPLES, N_SOURCES)
    # unit-variance, uncorrelated sources on the training data, as scikit-learn's whiten="unit-variance"
    np.testing.assert_allclose(np.cov(sources, rowvar=False, bias=True), np.eye(N_SOURCES), atol=1e-3)


@pytest.mark.parametrize("fun", ["logcosh", "exp", "cube"])
@pytest.mark.parametrize("whiten_solver", ["eigh", "svd"])
def test_agrees_with_scikit_learn(mixture, fun, whiten_solver):
    data, mixing = mixture
    ours = estimator(TorchFastICA, N_SOURCES, max_iter=200, tol=1e-4, seed=3, fun=fun, whiten_solver=whiten_solver).fit(
        data
    )
    reference = FastICA(
        N_SOURCES, fun=fun, whiten="unit-variance", whiten_solver=whiten_solver, max_iter=200, tol=1e-4, random_state=3
    ).fit(data)
    # Same start (scikit-learn's initial matrix for the seed), same iteration: same answer up to rounding.
    assert abs(ours.n_iter_ - reference.n_iter_) <= 1
    assert amari_distance(ours.components_, mixing) <= amari_distance(reference.components_, mixing) + 0.005
    np.testing.assert_allclose(ours.mean_, reference.mean_, atol=1e-5)
    np.testing.assert_allclose(ours.transform(data), reference.transform(data), atol=2e-3)


def test_deterministic_for_a_seed(mixture):
    data, _ = mixture
    first = estimator(TorchFastICA, N_SOURCES, seed=7).fit(data)
    second = estimator(TorchFastICA, N_SOURCES, seed=7).fit(data)
    for key, value in first.to_arrays().items():
        np.testing.assert_array_equal(second.to_arrays()[key], value)
    other = estimator(TorchFastICA, N_SOURCES, seed=8).fit(data)
    assert not np.array_equal(other.unmixing_, first.unmixing_)


def test_progress_bar_counts_iterations_and_changes_nothing(mixture, capsys):
    data, _ = mixture
    quiet = estimator(TorchFastICA, N_SOURCES, max_iter=30, seed=2).fit(data)
    shown = estimator(TorchFastICA, N_SOURCES, max_iter=30, seed=2).fit(data, progress=True)
    bar = capsys.readouterr().err
    assert "FastICA iterations" in bar and f"{shown.n_iter_}/30" in bar
    np.testing.assert_array_equal(shown.unmixing_, quiet.unmixing_)


def test_converged_flag_is_honest(mixture):
    data, _ = mixture
    stopped = estimator(TorchFastICA, N_SOURCES, max_iter=1, tol=1e-4, seed=0).fit(data)
    assert stopped.converged_ is False and stopped.n_iter_ == 1 and stopped.criterion_ >= 1e-4
    finished = estimator(TorchFastICA, N_SOURCES, max_iter=500, tol=1e-4, seed=0).fit(data)
    assert finished.converged_ is True and finished.n_iter_ < 500 and finished.criterion_ < 1e-4


def test_bad_input_raises(mixture):
    data, _ = mixture
    with pytest.raises(ValueError, match="n_components = 17 exceeds"):
        estimator(TorchFastICA, 17).fit(data)
    # 10 samples centred have rank 9: the 10th direction is rounding noise.
    few = np.random.default_rng(0).normal(size=(10, N_FEATURES)).astype(np.float32)
    for whiten_solver in ("eigh", "svd"):
        estimator(TorchFastICA, 9, whiten_solver=whiten_solver).fit(few)
        with pytest.raises(ValueError, match="n_components = 10 exceeds the 9 directions"):
            estimator(TorchFastICA, 10, whiten_solver=whiten_solver).fit(few)
    with pytest.raises(ValueError, match="fun"):
        estimator(TorchFastICA, 3, fun="tanh")
    with pytest.raises(ValueError, match="whiten_solver"):
        estimator(TorchFastICA, 3, whiten_solver="qr")


@pytest.mark.skipif(not torch.cuda.is_available(), reason="no CUDA device")
def test_cuda_matches_cpu(mixture):
    data, mixing = mixture
    cpu = estimator(TorchFastICA, N_SOURCES, seed=0, device="cpu").fit(data)
    cuda = estimator(TorchFastICA, N_SOURCES, seed=0, device="cuda").fit(data)
    assert abs(cuda.n_iter_ - cpu.n_iter_) <= 1
    assert amari_distance(cuda.components_, mixing) < 0.03
    np.testing.assert_allclose(cuda.transform(data), cpu.transform(data), atol=2e-3)


def test_ica_learner_fastica_solver_saves_and_loads_identically(tmp_path):
    train, test = images(600, 0), images(50, 1)
    # the relative gradient FastICA reaches on its own change_tol decides converged: a tol it meets
    params = {"n_components": 8, "solver": "fastica", "device": "cpu", "tol": 1e-3}
    learner = get_learner("ica")(learner_params("ica", params), seed=2)
    info = learner.fit(train, progress=False)
    assert info["solver"] == "fastica" and info["device"] == "cpu" and info["converged"] is True
    assert info["own_criterion"]["name"] == "change" and info["own_criterion"]["met"] is True
    assert info["convergence_warnings"] == [] and 1 <= info["n_iter"] < info["max_iter"]
    descriptors = learner.describe(test)
    # The descriptor is the projection on the unmixing matrix (after centring and whitening).
    estimator = learner.estimator
    expected = (to_float(test).reshape(len(test), -1) - estimator.mean_) @ (
        estimator.unmixing_ @ estimator.whitening_
    ).T
    np.testing.assert_allclose(descriptors, expected, rtol=1e-5, atol=1e-5)

    learner.save(tmp_path)
    assert (tmp_path / "ica.npz").is_file() and not (tmp_path / "fastica.joblib").exists()
    loaded = load_learner(tmp_path)
    assert loaded.params == learner.params and loaded.fit_info == learner.fit_info
    assert learner.fit_info == {key: value for key, value in info.items() if key not in RUN_KEYS}
    np.testing.assert_array_equal(loaded.describe(test), descriptors)

    # Same data, scikit-learn solver: the same descriptors up to float32 rounding.
    reference = get_learner("ica")(learner_params("ica", {**params, "solver": "sklearn", "device": "auto"}), seed=2)
    reference.fit(train, progress=False)
    np.testing.assert_allclose(reference.describe(test), descriptors, atol=1e-2)
    reference.save(tmp_path / "sklearn")
    assert (tmp_path / "sklearn" / "fastica.joblib").is_file()
    np.testing.assert_array_equal(load_learner(tmp_path / "sklearn").describe(test), reference.describe(test))


def test_ica_learner_fastica_solver_records_non_convergence_and_checks_params():
    learner = get_learner("ica")(learner_params("ica", {"n_components": 8, "max_iter": 2, "solver": "fastica"}), seed=0)
    info = learner.fit(images(200, 0), progress=False)
    assert info["converged"] is False and info["n_iter"] == info["max_iter"] == 2
    assert info["convergence_warnings"]
    with pytest.raises(ValueError, match=r"ica\.algorithm"):
        get_learner("ica")(learner_params("ica", {"solver": "fastica", "algorithm": "deflation"}))
    with pytest.raises(ValueError, match=r"ica\.solver"):
        get_learner("ica")(learner_params("ica", {"solver": "jax"}))
    with pytest.raises(ValueError, match=r"ica\.device"):
        get_learner("ica")(learner_params("ica", {"solver": "sklearn", "device": "cuda"}))


def test_whitening_is_white_for_ill_conditioned_data():
    """The whitened training data has unit covariance to ~5e-6 even when the kept variances span
    4 decades; with a float32 eigen-decomposition of the covariance it is ~6e-5 off here (1.4e-3 on
    benchmarks/speed/bench_ica.py's images, where FastICA then wanders instead of converging)."""
    rng = np.random.default_rng(0)
    rotation, _ = np.linalg.qr(rng.normal(size=(256, 256)))
    data = (0.5 + rng.laplace(size=(6000, 256)) * np.logspace(0, -2, 256) @ rotation).astype(np.float32)
    ica = estimator(TorchFastICA, 192, seed=0, whiten_solver="eigh")
    mean = torch.from_numpy(data.mean(axis=0, dtype=np.float64).astype(np.float32))
    whitened = ica._project(data, mean, ica._whitening(data, mean)).double()
    covariance = whitened @ whitened.T / whitened.shape[1]
    assert float((covariance - torch.eye(192, dtype=torch.float64)).abs().max()) < 2e-5


@pytest.mark.parametrize("solver", list(ICA_SOLVERS))
@pytest.mark.parametrize("whiten_solver", list(WHITEN_SOLVERS))
def test_every_registered_ica_solver_and_whitening_fits_saves_and_loads(tmp_path, solver, whiten_solver):
    train, test = images(300, 0), images(20, 1)
    precision = "float64" if solver == "python_picard" else "float32"
    learner = get_learner("ica")(
        learner_params(
            "ica",
            {
                "n_components": 6,
                "solver": solver,
                "whiten_solver": whiten_solver,
                "device": "cpu",
                "precision": precision,
            },
        ),
        seed=1,
    )
    info = learner.fit(train, progress=False)
    assert info["solver"] == solver and info["n_components"] == 6
    learner.save(tmp_path)
    np.testing.assert_array_equal(load_learner(tmp_path).describe(test), learner.describe(test))


def test_unknown_solvers_are_one_line_errors_naming_the_key_and_the_choices():
    for params, message in (
        ({"solver": "jax"}, "ica.solver: unknown value 'jax' (known: picard, python_picard, fastica, sklearn)"),
        ({"whiten_solver": "qr"}, "ica.whiten_solver: unknown value 'qr' (known: eigh, svd)"),
        (
            {"solver": "fastica", "algorithm": "deflation"},
            "ica.algorithm = 'deflation' needs ica.solver = 'sklearn' "
            "(the fastica solver implements the parallel algorithm)",
        ),
        ({"solver": "sklearn", "device": "cuda"}, "ica.device = 'cuda' needs ica.solver = 'picard' or 'fastica'"),
        (
            {"solver": "python_picard", "precision": "float32"},
            "ica.precision = 'float32' needs ica.solver = 'picard' or 'fastica' or 'sklearn'",
        ),
    ):
        with pytest.raises(ValueError) as error:
            get_learner("ica")(learner_params("ica", params))
        assert str(error.value) == message
    with pytest.raises(ValueError, match="whiten_solver must be one of eigh, svd, got 'qr'"):
        estimator(TorchFastICA, 3, whiten_solver="qr")
