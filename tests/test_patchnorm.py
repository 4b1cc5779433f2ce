import numpy as np
import pytest

from seasonloop.data.patchnorm import patch_normalise


def _patches(images: np.ndarray, size: int) -> np.ndarray:
    """(N, H, W) -> (N * rows * cols, size * size) by explicit slicing, as an independent reference."""
    return np.stack(
        [
            image[row : row + size, col : col + size].ravel()
            for image in images
            for row in range(0, images.shape[1], size)
            for col in range(0, images.shape[2], size)
        ]
    )


@pytest.fixture
def images() -> np.ndarray:
    return np.random.default_rng(0).integers(0, 256, size=(3, 16, 24), dtype=np.uint8)


def test_zscore_gives_each_patch_zero_mean_unit_std(images):
    normalised = patch_normalise(images, patch_size=8)
    assert normalised.dtype == np.float32 and normalised.shape == images.shape
    patches = _patches(normalised, 8)
    assert patches.shape == (3 * 2 * 3, 64)
    np.testing.assert_allclose(patches.mean(axis=1), 0.0, atol=1e-5)
    np.testing.assert_allclose(patches.std(axis=1), 1.0, atol=1e-5)


def test_zscore_matches_per_patch_reference(images):
    reference = _patches(images.astype(np.float64), 4)
    reference = (reference - reference.mean(axis=1, keepdims=True)) / reference.std(axis=1, keepdims=True)
    np.testing.assert_allclose(_patches(patch_normalise(images, 4), 4), reference, atol=1e-5)


def test_minmax_maps_each_patch_onto_zero_one(images):
    patches = _patches(patch_normalise(images, patch_size=4, mode="minmax"), 4)
    np.testing.assert_allclose(patches.min(axis=1), 0.0, atol=1e-6)
    np.testing.assert_allclose(patches.max(axis=1), 1.0, atol=1e-6)


def test_single_image_and_rectangular_patches(images):
    single = patch_normalise(images[0], patch_size=(8, 4))
    assert single.shape == images[0].shape
    np.testing.assert_array_equal(single, patch_normalise(images[:1], patch_size=(8, 4))[0])
    block = single[8:16, 4:8]  # one 8x4 patch
    assert abs(block.mean()) < 1e-5 and abs(block.std() - 1.0) < 1e-5


def test_flat_patch_becomes_zero_not_nan():
    flat = np.full((1, 8, 8), 7, dtype=np.uint8)
    for mode in ("zscore", "minmax"):
        np.testing.assert_array_equal(patch_normalise(flat, 8, mode=mode), 0.0)


@pytest.mark.parametrize("shape, patch_size", [((2, 16, 20), 8), ((10, 16), (3, 4)), ((2, 16, 16), 0)])
def test_bad_sizes_raise(shape, patch_size):
    with pytest.raises(ValueError):
        patch_normalise(np.zeros(shape, dtype=np.uint8), patch_size=patch_size)


def test_bad_mode_and_ndim_raise(images):
    with pytest.raises(ValueError, match="mode"):
        patch_normalise(images, 8, mode="l2")
    with pytest.raises(ValueError, match="shape"):
        patch_normalise(images[None], 8)
