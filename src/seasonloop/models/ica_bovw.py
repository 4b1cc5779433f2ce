"""ICA on image patches + bag of visual words: each image becomes a histogram of word counts."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from seasonloop.models.core.learner import EpochCallback, FeatureLearner, to_float, with_contiguous_arrays
from seasonloop.params.checks import integer, number, one_of

if TYPE_CHECKING:
    from sklearn.cluster import KMeans, MiniBatchKMeans
    from sklearn.decomposition import FastICA

ESTIMATORS_FILE = "ica_bovw.joblib"
KMEANS_N_INIT = 3
KMEANS_KINDS = ("minibatch", "full")  # ica_bovw.kmeans: scikit-learn's MiniBatchKMeans or KMeans


def extract_patches(images: np.ndarray, patch_size: int, stride: int) -> np.ndarray:
    """All patch_size x patch_size windows of (N, H, W) images every `stride` pixels, as a
    strided view of shape (N, rows, cols, patch_size, patch_size) (no copy)."""
    windows = sliding_window_view(images, (patch_size, patch_size), axis=(1, 2))
    return windows[:, ::stride, ::stride]


def remove_dc(patches: np.ndarray) -> np.ndarray:
    """(n, p, p) patches -> (n, p*p) float64 rows with each patch's own mean subtracted.

    float64 from here on (the patch ICA, the k-means words and their assignment): in float32 the
    BLAS kernels of another CPU (OpenBLAS picks them per CPU) round differently, k-means then
    follows another path and every descriptor changes (up to 3 points of fraction correct);
    in float64 those differences stay far below any assignment's margin. It costs little: patches
    have 64 pixels."""
    rows = patches.reshape(len(patches), -1).astype(np.float64)
    return rows - rows.mean(axis=1, keepdims=True)


class ICABoVW(FeatureLearner):
    """FastICA on DC-removed patches, k-means words on the ICA sources, L1-normalised histograms."""

    name = "ica_bovw"
    figures = ("patch_ica",)  # the study's Figures 12 (filters) and 13 (visual words)
    TINY_RUN = {"n_train_patches": 3000, "n_components": 15, "n_words": 20}
    LIBRARIES = ("sklearn.cluster", "sklearn.decomposition", "joblib", "seasonloop.models.core.fastica_sklearn")
    PARAMS = {
        "patch_size": integer(1),
        "stride": integer(1),
        "n_train_patches": integer(2),
        "n_components": integer(1),
        "n_words": integer(1),
        "kmeans": one_of(*KMEANS_KINDS),
        "max_iter": integer(1),
        "tol": number(0, None, low_open=True),
    }

    @classmethod
    def how_fit_ended(cls, info: Mapping[str, Any]) -> dict[str, Any]:
        """The patch ICA's ending (its info nested under "ica") and k-means' iterations."""
        ended = super().how_fit_ended(info)
        nested = info.get("ica")
        if isinstance(nested, Mapping):
            ended.update({f"ica {key}": value for key, value in super().how_fit_ended(nested).items()})
        if "kmeans_n_iter" in info:
            ended["kmeans n_iter"] = info["kmeans_n_iter"]
        return ended

    def __init__(self, params: Mapping[str, Any], seed: int = 0):
        super().__init__(params, seed)
        self.ica: FastICA | None = None
        self.kmeans: KMeans | MiniBatchKMeans | None = None

    def _validate_params(self) -> None:
        patch_size, n_components = self.params["patch_size"], self.params["n_components"]
        if n_components > patch_size**2 - 1:
            raise ValueError(
                f"{self._key('n_components')} = {n_components} exceeds {patch_size**2 - 1}: patches of "
                f"{patch_size}x{patch_size} with their mean removed span only patch_size**2 - 1 dimensions"
            )

    def _patch_words(self, images: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Patches (n_images, n_patches, p, p) float32 in [0, 1] and their word index (n_images, n_patches)."""
        patch_size = self.params["patch_size"]
        windows = extract_patches(to_float(images), patch_size, self.params["stride"])
        patches = windows.reshape(len(images), -1, patch_size, patch_size)
        assert self.ica is not None and self.kmeans is not None, "describe checks that the learner is fitted"
        sources = self.ica.transform(remove_dc(patches.reshape(-1, patch_size, patch_size)))
        words = self.kmeans.predict(sources)
        return patches, words.reshape(len(images), -1)

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        from sklearn.cluster import KMeans, MiniBatchKMeans

        from seasonloop.models.core.fastica_sklearn import fit_fastica

        patch_size, stride = self.params["patch_size"], self.params["stride"]
        height, width = self.image_shape
        if patch_size > min(height, width):
            raise ValueError(f"{self._key('patch_size')} = {patch_size} exceeds the image size {height}x{width}")
        windows = extract_patches(images, patch_size, stride)
        n_rows, n_cols = windows.shape[1:3]
        n_available = len(images) * n_rows * n_cols
        # Sample flat patch indices, then copy only those patches out of the strided view.
        rng = np.random.default_rng(self.seed)
        n_used = min(self.params["n_train_patches"], n_available)
        if self.params["n_words"] > n_used:
            raise ValueError(f"{self._key('n_words')} = {self.params['n_words']} exceeds the {n_used} training patches")
        flat_index = np.sort(rng.choice(n_available, size=n_used, replace=False))
        image_index, row_index, col_index = np.unravel_index(flat_index, (len(images), n_rows, n_cols))
        patches = to_float(windows[image_index, row_index, col_index])
        self.ica, convergence = fit_fastica(
            remove_dc(patches),
            n_components=self.params["n_components"],
            max_iter=self.params["max_iter"],
            tol=self.params["tol"],
            seed=self.seed,
            # scikit-learn's own defaults (not settings of this learner)
            algorithm="parallel",
            fun="logcosh",
            # With n_samples >> 64 features both solvers are fast; svd copes better with the
            # null direction that DC removal creates.
            whiten_solver="svd",
        )
        sources = self.ica.transform(remove_dc(patches))
        kmeans_class = MiniBatchKMeans if self.params["kmeans"] == "minibatch" else KMeans
        self.kmeans = with_contiguous_arrays(
            kmeans_class(n_clusters=self.params["n_words"], n_init=KMEANS_N_INIT, random_state=self.seed).fit(sources)
        )
        return {
            "n_train_images": len(images),
            "patches_per_image": n_rows * n_cols,
            "n_train_patches_available": n_available,
            "n_train_patches": n_used,
            "ica": convergence,
            "kmeans_n_iter": int(self.kmeans.n_iter_),
            "kmeans_inertia": float(self.kmeans.inertia_),
        }

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        _, words = self._patch_words(images)
        n_words = self.params["n_words"]
        # One bincount over (image, word) pairs gives every image's histogram at once.
        offsets = np.arange(len(images))[:, None] * n_words
        counts = np.bincount((words + offsets).ravel(), minlength=len(images) * n_words)
        counts = counts.reshape(len(images), n_words).astype(np.float32)
        return counts / counts.sum(axis=1, keepdims=True)

    def filters(self) -> np.ndarray:
        """The learned independent components as (n_components, p, p) patches (mixing matrix columns)."""
        self._require_fitted("filters")
        assert self.ica is not None
        patch_size = self.params["patch_size"]
        return self.ica.mixing_.T.reshape(-1, patch_size, patch_size).astype(np.float32)

    def word_examples(self, images: np.ndarray, n_words: int, n_examples: int) -> np.ndarray:
        """(n_words, n_examples, p, p) float32 patches of the n_words most frequent words in `images`
        (most frequent first), each word's patches those nearest its centre; slots left when a word
        has fewer patches than n_examples are NaN."""
        images = self._check_describe_input(images, "word_examples")
        if not 1 <= n_words <= self.params["n_words"] or n_examples < 1:
            raise ValueError(
                f"need 1 <= n_words <= {self.params['n_words']} and n_examples >= 1, "
                f"got n_words={n_words}, n_examples={n_examples}"
            )
        patch_size = self.params["patch_size"]
        patches, words = self._patch_words(images)
        patches = patches.reshape(-1, patch_size, patch_size)
        words = words.ravel()
        assert self.ica is not None and self.kmeans is not None
        sources = self.ica.transform(remove_dc(patches))
        distances = self.kmeans.transform(sources)
        counts = np.bincount(words, minlength=self.params["n_words"])
        # Stable sort keeps ties in word-index order, so the choice is deterministic.
        top_words = np.argsort(-counts, kind="stable")[:n_words]
        examples = np.full((n_words, n_examples, patch_size, patch_size), np.nan, dtype=np.float32)
        for slot, word in enumerate(top_words):
            members = np.flatnonzero(words == word)
            nearest = members[np.argsort(distances[members, word], kind="stable")[:n_examples]]
            examples[slot, : len(nearest)] = patches[nearest]
        return examples

    def _save_state(self, directory: Path) -> None:
        import joblib

        joblib.dump({"ica": self.ica, "kmeans": self.kmeans}, directory / ESTIMATORS_FILE)

    def _load_state(self, directory: Path) -> None:
        import joblib

        estimators = joblib.load(directory / ESTIMATORS_FILE)
        self.ica, self.kmeans = estimators["ica"], estimators["kmeans"]
