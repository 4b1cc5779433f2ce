"""Global ICA on whole training images; descriptor = projection on the unmixing matrix.

ICA_SOLVERS is the registry of ica.solver values. All of them centre, whiten to n_components
principal axes and look for the orthogonal unmixing of the whitened data that is a stationary
point of the same contrast (log cosh for fun "logcosh"); they differ in how they get there:

- "picard" (params.yaml's): Picard-O, L-BFGS under the orthogonal constraint, in torch (float32 or
  float64, CUDA when present; seasonloop.models.core.picard.TorchPicard). It stops when the
  relative gradient is below ica.tol.
- "python_picard": the same algorithm by python-picard itself (float64 numpy, the CPU).
- "fastica": FastICA's parallel fixed point in torch (seasonloop.models.core.fastica).
- "sklearn": scikit-learn's FastICA (parallel or deflation).

FastICA stops on its own test, the change of W between iterations below ica.change_tol, which
says how far one step moves W, not how far W is from a stationary point. So every solver's fit
record reports the same stationarity measure, the max |entry| of the relative gradient
(seasonloop.models.core.ica_stationarity.relative_gradient), and `converged` means exactly that it is
below ica.tol; the solver's own test is recorded beside it. benchmarks/speed/bench_ica.py compares them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from seasonloop.models.core.arithmetic import DEVICES
from seasonloop.models.core.learner import EpochCallback, FeatureLearner, select_training_subset, to_float
from seasonloop.params.checks import integer, number, one_of

if TYPE_CHECKING:
    from sklearn.decomposition import FastICA

    from seasonloop.models.core.torch_ica import TorchICA

ESTIMATOR_FILE = "fastica.joblib"
TORCH_STATE_FILE = "ica.npz"
# scikit-learn FastICA's algorithm, fun and whiten_solver values; the torch solvers implement the
# same fun and whiten_solver values (models/core/ica_densities.py, models/core/torch_ica.py)
ICA_ALGORITHMS = ("parallel", "deflation")
ICA_FUNCTIONS = ("logcosh", "exp", "cube")
WHITEN_SOLVERS = ("eigh", "svd")
ICA_PRECISIONS = ("float32", "float64")  # the ICA iterations' arithmetic


@dataclass(frozen=True)
class ICASolver:
    """One value of ica.solver: the ica.algorithm, ica.device and ica.precision values it takes;
    fit(learner, flat images, progress) sets learner.estimator and returns its fit record (from
    "solver" on); save(estimator, directory) and load(learner, directory) -> estimator keep it on disk."""

    algorithms: tuple[str, ...]
    devices: tuple[str, ...]
    precisions: tuple[str, ...]
    fit: Callable[[ICALearner, np.ndarray, bool], dict[str, Any]]
    save: Callable[[Any, Path], None]
    load: Callable[[ICALearner, Path], Any]


def _record(
    learner: ICALearner, solver: str, gradient: float, n_iter: int, own: dict[str, Any], **more: Any
) -> dict[str, Any]:
    """The fit record every solver writes: converged = the relative gradient below ica.tol; `own`
    is the solver's own stopping test (its name, last value, tolerance and whether it was met)."""
    tol = learner.params["tol"]
    converged = gradient < tol
    messages = (
        []
        if converged
        else [
            f"ICA ({solver}) did not converge in {n_iter} iterations: relative gradient {gradient:.3g} >= "
            f"ica.tol {tol:.3g} ({own['name']} {own['value']:.3g}, own test met: {own['met']}); raise ica.max_iter"
        ]
    )
    return {
        "solver": solver,
        **more,
        "n_iter": int(n_iter),
        "max_iter": int(learner.params["max_iter"]),
        "gradient": float(gradient),
        "tol": float(tol),
        "converged": bool(converged),
        "own_criterion": own,
        "convergence_warnings": messages,
    }


def _fit_sklearn(learner: ICALearner, flat: np.ndarray, progress: bool) -> dict[str, Any]:
    from seasonloop.models.core.fastica_sklearn import fit_fastica
    from seasonloop.models.core.ica_stationarity import relative_gradient

    data = flat.astype(np.float64) if learner.params["precision"] == "float64" else flat
    learner.estimator, convergence = fit_fastica(
        data,
        n_components=learner.params["n_components"],
        max_iter=learner.params["max_iter"],
        tol=learner.params["change_tol"],
        seed=learner.seed,
        algorithm=learner.params["algorithm"],
        fun=learner.params["fun"],
        whiten_solver=learner.params["whiten_solver"],
    )
    gradient = relative_gradient(learner.estimator.transform(data), learner.params["fun"])
    # scikit-learn does not return its last change, only whether it stopped on it
    own = {
        "name": "change",
        "value": float("nan"),
        "tol": learner.params["change_tol"],
        "met": convergence["converged"],
    }
    return _record(learner, "sklearn", gradient, convergence["n_iter"], own, algorithm=learner.params["algorithm"])


def _save_sklearn(estimator: FastICA, directory: Path) -> None:
    import joblib

    joblib.dump(estimator, directory / ESTIMATOR_FILE)


def _load_sklearn(learner: ICALearner, directory: Path) -> FastICA:
    import joblib

    return joblib.load(directory / ESTIMATOR_FILE)


def _torch_picard() -> type[TorchICA]:
    from seasonloop.models.core.picard import TorchPicard

    return TorchPicard


def _library_picard() -> type[TorchICA]:
    from seasonloop.models.core.picard import LibraryPicard

    return LibraryPicard


def _torch_fastica() -> type[TorchICA]:
    from seasonloop.models.core.fastica import TorchFastICA

    return TorchFastICA


def _torch_solver(
    name: str, estimator_class: Callable[[], type[TorchICA]], devices: tuple[str, ...], precisions: tuple[str, ...]
) -> ICASolver:
    """A solver built on TorchICA (whitening, saving and describing shared; the class that
    `estimator_class` imports, when a fit or load needs torch, rotates)."""

    def fit(learner: ICALearner, flat: np.ndarray, progress: bool) -> dict[str, Any]:
        from seasonloop.models.core.arithmetic import resolve_device

        device = resolve_device(learner.params["device"], learner._key("device"))
        fitted = learner._torch_estimator(estimator_class(), device)
        try:
            fitted.fit(flat, progress=progress)
        except ValueError as error:
            raise ValueError(f"{learner.name}: {error}") from error
        learner.estimator = fitted
        assert fitted.n_iter_ is not None and fitted.gradient_ is not None and fitted.criterion_ is not None
        own = {
            "name": fitted.criterion_name,
            "value": fitted.criterion_,
            "tol": fitted.tol,
            "met": bool(fitted.converged_),
        }
        # TorchPicard's counts of what slowed it (its class doc), where the solver has them
        diagnostics = {
            key: getattr(fitted, f"{key}_") for key in ("sign_changes", "gradient_steps") if hasattr(fitted, f"{key}_")
        }
        return _record(
            learner,
            name,
            fitted.gradient_,
            fitted.n_iter_,
            own,
            device=str(device),
            precision=fitted.precision,
            **diagnostics,
        )

    def save(fitted: TorchICA, directory: Path) -> None:
        np.savez(directory / TORCH_STATE_FILE, **fitted.to_arrays())  # type: ignore[arg-type]  # numpy's stubs

    def load(learner: ICALearner, directory: Path) -> TorchICA:
        path = directory / TORCH_STATE_FILE
        if not path.is_file():
            raise FileNotFoundError(f"no saved ICA state: {path} does not exist")
        with np.load(path) as arrays:
            # The arrays alone define the model; describe() runs in numpy on any machine.
            return learner._torch_estimator(estimator_class(), "cpu").load_arrays(dict(arrays))

    return ICASolver(("parallel",), devices, precisions, fit, save, load)


# A new solver is one ICASolver line here (and its functions above, or a TorchICA subclass that a
# function above imports: this module is imported by every stage's params check, torch is not).
ICA_SOLVERS: dict[str, ICASolver] = {
    "picard": _torch_solver("picard", _torch_picard, DEVICES, ICA_PRECISIONS),
    "python_picard": _torch_solver("python_picard", _library_picard, ("auto", "cpu"), ("float64",)),
    "fastica": _torch_solver("fastica", _torch_fastica, DEVICES, ICA_PRECISIONS),
    "sklearn": ICASolver(ICA_ALGORITHMS, ("auto", "cpu"), ICA_PRECISIONS, _fit_sklearn, _save_sklearn, _load_sklearn),
}


class ICALearner(FeatureLearner):
    """ICA on flattened training images; descriptor = its sources (transform).

    The ica.solver entry of ICA_SOLVERS fits, saves and loads the estimator (module doc); the torch
    solvers are saved as plain numpy arrays (mean, whitening, unmixing), scikit-learn's with joblib.
    """

    name = "ica"
    figures = ("ica_basis",)  # its basis images
    TINY_RUN = {"n_components": 16, "max_iter": 200}
    LIBRARIES = (  # every solver's (which one fits is ica.solver's choice)
        "joblib",
        "seasonloop.models.core.arithmetic",
        "seasonloop.models.core.fastica",
        "seasonloop.models.core.fastica_sklearn",
        "seasonloop.models.core.ica_stationarity",
        "seasonloop.models.core.picard",
    )
    PARAMS = {
        "n_components": integer(1),
        "algorithm": one_of(*ICA_ALGORITHMS),
        "fun": one_of(*ICA_FUNCTIONS),
        "max_iter": integer(1),
        "tol": number(0, None, low_open=True),
        "change_tol": number(0, None, low_open=True),
        "whiten_solver": one_of(*WHITEN_SOLVERS),
        "max_train_images": integer(0),
        "solver": one_of(*ICA_SOLVERS),
        "device": one_of(*DEVICES),
        "precision": one_of(*ICA_PRECISIONS),
    }

    def __init__(self, params: Mapping[str, Any], seed: int = 0):
        super().__init__(params, seed)
        self.estimator: FastICA | TorchICA | None = None

    @property
    def solver(self) -> ICASolver:
        return ICA_SOLVERS[self.params["solver"]]

    def _validate_params(self) -> None:
        self._check_solver_takes(
            "algorithm",
            "algorithms",
            f" (the {self.params['solver']} solver implements the {' and '.join(self.solver.algorithms)} algorithm)",
        )
        self._check_solver_takes("device", "devices")
        self._check_solver_takes("precision", "precisions")

    def _check_solver_takes(self, key: str, field: str, why: str = "") -> None:
        """A one-line error naming `key` when the chosen solver does not take its value (its ICASolver
        `field` does not list it), naming the solvers that do."""
        value = self.params[key]
        if value not in getattr(self.solver, field):
            able = " or ".join(repr(name) for name, solver in ICA_SOLVERS.items() if value in getattr(solver, field))
            raise ValueError(f"{self._key(key)} = {value!r} needs {self._key('solver')} = {able}{why}")

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        subset, subset_info = select_training_subset(images, self.params["max_train_images"], self.seed)
        flat = to_float(subset).reshape(len(subset), -1)
        limit = min(flat.shape)
        if self.params["n_components"] > limit:
            # FastICA would silently lower it; make the caller choose.
            raise ValueError(
                f"{self._key('n_components')} = {self.params['n_components']} exceeds {limit}, the most "
                f"{len(flat)} training images of {flat.shape[1]} pixels allow"
            )
        return {**subset_info, "n_components": self.params["n_components"], **self.solver.fit(self, flat, progress)}

    def _torch_estimator(self, estimator: type[TorchICA], device: Any) -> TorchICA:
        # the solver's own stopping tolerance: the relative gradient (Picard) or the change (FastICA)
        own_tol = self.params["tol"] if estimator.criterion_name == "gradient" else self.params["change_tol"]
        return estimator(
            n_components=self.params["n_components"],
            max_iter=self.params["max_iter"],
            tol=own_tol,
            seed=self.seed,
            fun=self.params["fun"],
            whiten_solver=self.params["whiten_solver"],
            device=device,
            precision=self.params["precision"],
        )

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        assert self.estimator is not None, "describe checks that the learner is fitted"
        return self.estimator.transform(to_float(images).reshape(len(images), -1)).astype(np.float32, copy=False)

    def _save_state(self, directory: Path) -> None:
        self.solver.save(self.estimator, directory)

    def _load_state(self, directory: Path) -> None:
        self.estimator = self.solver.load(self, directory)
