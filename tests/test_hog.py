"""The hog learner is VPR-Bench's HOG (VPR_Techniques/HOG_VPR.py), matched by cosine as VPR-Bench."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from seasonloop.evaluation.distances import distance_matrix
from seasonloop.models.core.lookup import get_learner
from tools.repository import learner_params


def vpr_bench_hog(image: np.ndarray) -> np.ndarray:
    """HOG_VPR.py compute_query_desc: its settings, written out."""
    win_size, block_size, block_stride, cell_size, nbins = (512, 512), (16, 16), (8, 8), (16, 16), 9
    hog = cv2.HOGDescriptor(win_size, block_size, block_stride, cell_size, nbins)
    return hog.compute(cv2.resize(image, win_size))


def vpr_bench_score(query_desc: np.ndarray, ref_desc: np.ndarray) -> float:
    """HOG_VPR.py perform_VPR: the cosine similarity of the two descriptors in float64."""
    query_desc, ref_desc = query_desc.astype("float64"), ref_desc.astype("float64")
    return float(np.dot(query_desc.T, ref_desc) / (np.linalg.norm(query_desc) * np.linalg.norm(ref_desc)))


def images(n: int, seed: int) -> np.ndarray:
    """Grey images with structure (a gradient and bright blocks), as the study's 32 x 64 ones."""
    rng = np.random.default_rng(seed)
    stack = np.tile(np.linspace(0, 200, 64, dtype=np.float64), (n, 32, 1))
    for image in stack:
        row, column = rng.integers(0, 24), rng.integers(0, 56)
        image[row : row + 8, column : column + 8] = rng.integers(100, 256)
    return (stack + rng.normal(0, 10, stack.shape)).clip(0, 255).astype(np.uint8)


def test_hog_is_vpr_benchs_descriptor_and_score():
    database, queries = images(5, 0), images(3, 1)
    learner = get_learner("hog")(learner_params("hog", {}), seed=0)
    learner.fit(database, progress=False)
    described = learner.describe(np.concatenate([database, queries]))
    expected = np.stack([vpr_bench_hog(image).ravel() for image in np.concatenate([database, queries])])
    np.testing.assert_array_equal(described, expected)
    # 63 x 63 blocks of one 16-pixel cell, 9 bins each
    assert described.shape == (8, 63 * 63 * 9) and described.dtype == np.float32
    # the pipeline's cosine distance is 1 - VPR-Bench's score
    distances = distance_matrix(described[:5], described[5:], metric="cosine")
    scores = np.array([[vpr_bench_score(vpr_bench_hog(q), vpr_bench_hog(r)) for r in database] for q in queries])
    np.testing.assert_allclose(1 - distances, scores, atol=1e-6)


def test_hog_settings_opencv_cannot_take_are_refused_by_name():
    with pytest.raises(ValueError, match=r"hog\.block = 16 and hog\.block_stride = 7 do not tile hog\.size = 512"):
        get_learner("hog")(learner_params("hog", {"block_stride": 7}), seed=0)
    with pytest.raises(ValueError, match=r"hog\.cell = 12 .* must divide hog\.block = 16"):
        get_learner("hog")(learner_params("hog", {"cell": 12}), seed=0)
