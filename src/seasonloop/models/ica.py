"""Global ICA: FastICA on whole training images; descriptor = projection on the unmixing matrix.

ICA_SOLVERS is the registry of ica.solver values, two solvers of the same algorithm: "torch"
(default; seasonloop.models.core.fastica.TorchFastICA, float32, CUDA when present, parallel algorithm only;
benchmarks/bench_ica.py compares them) or "sklearn" (scikit-learn's FastICA, which also offers the
deflation algorithm). Each says what it implements, fits, saves and loads; ICALearner only
dispatches. Both take the whitening solvers of seasonloop.models.core.fastica.WHITEN_SOLVERS (eigh, svd).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import joblib
import numpy as np
import torch
from sklearn.decomposition import FastICA

from seasonloop.models.core.fastica import TorchFastICA
from seasonloop.models.core.fastica_sklearn import fit_fastica
from seasonloop.models.core.learner import EpochCallback, FeatureLearner, select_training_subset, to_float
from seasonloop.models.core.torch_learner import resolve_device
from seasonloop.params.learners import DEVICES, ICA_ALGORITHMS

ESTIMATOR_FILE = "fastica.joblib"
TORCH_STATE_FILE = "fastica.npz"


@dataclass(frozen=True)
class ICASolver:
    """One value of ica.solver: the ica.algorithm and ica.device values it takes; fit(learner,
    flat images, progress) sets learner.estimator and returns its fit record (from "solver" on);
    save(estimator, directory) and load(learner, directory) -> estimator keep it on disk."""

    algorithms: tuple[str, ...]
    devices: tuple[str, ...]
    fit: Callable[[ICALearner, np.ndarray, bool], dict[str, Any]]
    save: Callable[[Any, Path], None]
    load: Callable[[ICALearner, Path], Any]


def _fit_sklearn(learner: ICALearner, flat: np.ndarray, progress: bool) -> dict[str, Any]:
    learner.estimator, convergence = fit_fastica(
        flat,
        n_components=learner.params["n_components"],
        max_iter=learner.params["max_iter"],
        tol=learner.params["tol"],
        seed=learner.seed,
        algorithm=learner.params["algorithm"],
        fun=learner.params["fun"],
        whiten_solver=learner.params["whiten_solver"],
    )
    return {"solver": "sklearn", **convergence}


def _save_sklearn(estimator: FastICA, directory: Path) -> None:
    joblib.dump(estimator, directory / ESTIMATOR_FILE)


def _load_sklearn(learner: ICALearner, directory: Path) -> FastICA:
    return joblib.load(directory / ESTIMATOR_FILE)


def _fit_torch(learner: ICALearner, flat: np.ndarray, progress: bool) -> dict[str, Any]:
    device = resolve_device(learner.params["device"], learner._key("device"))
    estimator = learner._torch_estimator(device)
    try:
        estimator.fit(flat, progress=progress)
    except ValueError as error:
        raise ValueError(f"{learner.name}: {error}") from error
    learner.estimator = estimator
    assert estimator.n_iter_ is not None, "set by fit"
    messages = (
        []
        if estimator.converged_
        else [
            f"FastICA did not converge in {estimator.n_iter_} iterations (last change "
            f"{estimator.last_change_:.3g} >= tol {estimator.tol}); raise max_iter or tol"
        ]
    )
    return {
        "solver": "torch",
        "device": str(device),
        "n_iter": int(estimator.n_iter_),
        "max_iter": int(estimator.max_iter),
        "converged": bool(estimator.converged_),
        "convergence_warnings": messages,
    }


def _save_torch(estimator: TorchFastICA, directory: Path) -> None:
    np.savez(directory / TORCH_STATE_FILE, **estimator.to_arrays())  # type: ignore[arg-type]  # numpy's stubs


def _load_torch(learner: ICALearner, directory: Path) -> TorchFastICA:
    path = directory / TORCH_STATE_FILE
    if not path.is_file():
        raise FileNotFoundError(f"no saved torch FastICA state: {path} does not exist")
    with np.load(path) as arrays:
        # The arrays alone define the model; describe() runs in numpy on any machine.
        return learner._torch_estimator("cpu").load_arrays(dict(arrays))


# A new solver is one ICASolver line here (and its functions above).
ICA_SOLVERS: dict[str, ICASolver] = {
    "sklearn": ICASolver(ICA_ALGORITHMS, ("auto", "cpu"), _fit_sklearn, _save_sklearn, _load_sklearn),
    "torch": ICASolver(("parallel",), DEVICES, _fit_torch, _save_torch, _load_torch),
}


class ICALearner(FeatureLearner):
    """FastICA on flattened training images; descriptor = its sources (transform).

    The ica.solver entry of ICA_SOLVERS fits, saves and loads the estimator: "sklearn" uses
    scikit-learn; "torch" uses TorchFastICA on `device` and is saved as plain numpy arrays (mean,
    whitening, unmixing).
    """

    name = "ica"
    defaults = {
        "n_components": 128,
        "algorithm": "parallel",
        "fun": "logcosh",
        "max_iter": 400,
        "tol": 1e-4,
        "whiten_solver": "eigh",
        "max_train_images": 0,
        "solver": "torch",
        "device": "auto",
    }

    def __init__(self, params: Mapping[str, Any] | None = None, seed: int = 0):
        super().__init__(params, seed)
        self.estimator: FastICA | TorchFastICA | None = None

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

    def _torch_estimator(self, device: torch.device | str) -> TorchFastICA:
        return TorchFastICA(
            n_components=self.params["n_components"],
            max_iter=self.params["max_iter"],
            tol=self.params["tol"],
            seed=self.seed,
            fun=self.params["fun"],
            whiten_solver=self.params["whiten_solver"],
            device=device,
        )

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        assert self.estimator is not None, "describe checks that the learner is fitted"
        return self.estimator.transform(to_float(images).reshape(len(images), -1))

    def _save_state(self, directory: Path) -> None:
        self.solver.save(self.estimator, directory)

    def _load_state(self, directory: Path) -> None:
        self.estimator = self.solver.load(self, directory)
