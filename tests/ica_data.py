"""Test data of the ICA tests (test_fastica.py, test_picard.py): known sources mixed, and images."""

from __future__ import annotations

import numpy as np


def mixed_sources(n_samples: int, n_features: int, n_super: int, n_sub: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Super-Gaussian (Laplace) and sub-Gaussian (uniform) independent sources mixed into more
    features, plus a little noise: (n_samples, n_features) float32 data and the (n_features,
    n_sources) mixing matrix (seeded: the same arguments give the same data)."""
    rng = np.random.default_rng(0)
    sources = np.concatenate(
        [rng.laplace(size=(n_samples, n_super)), rng.uniform(-1.7, 1.7, size=(n_samples, n_sub))], axis=1
    )
    mixing = rng.normal(size=(n_features, n_super + n_sub))
    data = sources @ mixing.T + 0.01 * rng.normal(size=(n_samples, n_features))
    return data.astype(np.float32), mixing


def images(n: int, seed: int) -> np.ndarray:
    """uint8 (n, 8, 16) images: 8 fixed patterns weighted by independent Laplace sources, plus noise."""
    patterns = np.random.default_rng(100).normal(size=(8, 8 * 16))
    rng = np.random.default_rng(seed)
    pixels = 128 + 6 * rng.laplace(size=(n, 8)) @ patterns + rng.normal(0, 3, (n, 8 * 16))
    return np.clip(pixels, 0, 255).astype(np.uint8).reshape(n, 8, 16)


# The tests' own solver settings: the estimators take every setting explicitly (the pipeline's
# values are params.yaml's ica section); a test states only what it changes.
SETTINGS = {
    "max_iter": 200,
    "tol": 1e-4,
    "seed": 0,
    "fun": "logcosh",
    "whiten_solver": "eigh",
    "device": "cpu",
    "precision": "float32",
}


def estimator(solver: type, n_components: int, **changes: object) -> object:
    """solver(n_components) at SETTINGS with `changes`."""
    return solver(n_components, **{**SETTINGS, **changes})
