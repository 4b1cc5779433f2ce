"""The place-supervised learner (models/place_cnn.py): its batches of P places x K images, its
validation's recall across traverses, and a network that learns which images show one place."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from seasonloop.models.core.lookup import get_learner
from seasonloop.models.core.place_training import place_batches, recall_across_traverses
from seasonloop.models.core.training import validation_places
from tools.repository import learner_params

HEIGHT, WIDTH = 16, 32
N_PLACES = 16


def two_conditions(copies: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """N_PLACES textures (gratings of 8 orientations and 2 periods, a random phase each image) seen
    in two traverses, `copies` noisy images of each: the second traverse darker, flatter and under a
    gradient across the image, a change that the raw image does not see through; (uint8 images,
    place ids, traverses)."""
    rng = np.random.default_rng(seed)
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    angle = np.pi * (np.arange(N_PLACES) % 8) / 8
    period = np.where(np.arange(N_PLACES) < 8, 4.0, 8.0)
    ramp = np.linspace(0, 0.6, WIDTH)[None, :]
    images, places, traverses = [], [], []
    for traverse in (0, 1):
        for _ in range(copies):
            phase = rng.uniform(0, 2 * np.pi, N_PLACES)
            along = columns[None] * np.cos(angle)[:, None, None] + rows[None] * np.sin(angle)[:, None, None]
            shown = 0.5 + 0.4 * np.sin(2 * np.pi * along / period[:, None, None] + phase[:, None, None])
            if traverse:
                shown = 0.2 + 0.3 * shown + ramp
            noisy = shown + rng.normal(0, 0.05, shown.shape)
            images.append((np.clip(noisy, 0, 1) * 255).astype(np.uint8))
            places.append(np.arange(N_PLACES))
            traverses.append(np.full(N_PLACES, traverse))
    return np.concatenate(images), np.concatenate(places), np.concatenate(traverses)


TINY = {"channels": [4, 8], "dim": 16, "batch_size": 64, "learning_rate": 3e-3, "validation_block": 4}


def test_a_batch_is_p_places_of_k_images_each_every_label_at_least_twice():
    places = np.concatenate([np.repeat(np.arange(10), 6), [10, 11, 11]])  # place 10 has one image
    batches = place_batches(places, places_per_batch=4, images_per_place=3, rng=np.random.default_rng(0))
    seen = np.concatenate([np.unique(places[rows]) for rows in batches])
    # every place with two images or more (not 10) in one batch an epoch: 4 + 4 + 3 places
    assert sorted(seen) == [*range(10), 11] and [len(np.unique(places[rows])) for rows in batches] == [4, 4, 3]
    # a last batch of one place (no negative) is dropped
    assert len(place_batches(places[:-3], 5, 3, np.random.default_rng(0))) == 2
    for rows in batches:
        labels, counts = np.unique(places[rows], return_counts=True)
        assert 2 <= len(labels) <= 4 and (counts >= 2).all()
        assert all(count == min(3, (places == label).sum()) for label, count in zip(labels, counts))
        assert len(set(rows)) == len(rows)  # no image twice
    again = place_batches(places, 4, 3, np.random.default_rng(0))
    assert all(np.array_equal(a, b) for a, b in zip(batches, again))  # seeded


def test_recall_across_traverses_counts_the_nearest_image_of_another_traverse():
    descriptors = np.array([[1.0, 0.0], [0.0, 1.0], [0.9, 0.1], [0.1, 0.9], [1.0, 0.0]])
    descriptors /= np.linalg.norm(descriptors, axis=1, keepdims=True)
    places = np.array([0, 1, 0, 1, 5])  # place 5 only in traverse 0: not a query
    traverses = np.array([0, 0, 1, 1, 0])
    assert recall_across_traverses(descriptors, places, traverses) == 1.0
    swapped = np.array([0, 1, 1, 0, 5])
    assert recall_across_traverses(descriptors, swapped, traverses) == 0.0


def test_one_traverse_is_refused_with_the_reason():
    images, places, _ = two_conditions(copies=2)
    learner = get_learner("place_cnn")(learner_params("place_cnn", TINY), seed=0)
    with pytest.raises(ValueError, match="place_cnn: every training image is of one traverse"):
        learner.fit(images, progress=False, places=places)


def test_a_batch_too_small_for_two_places_is_refused_naming_the_key():
    with pytest.raises(ValueError, match=r"place_cnn\.batch_size = 6"):
        get_learner("place_cnn")(learner_params("place_cnn", {**TINY, "batch_size": 6}), seed=0)


def untrained(learner_class, params: dict, shape: tuple[int, int]):
    """The network a fit starts from (the same seed), described as a fitted learner would."""
    learner = learner_class(params, seed=0)
    learner.input_shape, learner.fit_info, learner._dtype = shape, {}, torch.float32
    learner.model = learner._seeded_model().eval()
    return learner


@pytest.fixture(scope="module")
def trained():
    images, places, traverses = two_conditions(copies=2)
    # four held-out places (16 validation images): with two, one lucky early epoch can be the best kept
    changes = {
        **TINY,
        "batch_size": 32,
        "validation_block": 2,
        "validation_fraction": 0.25,
        "max_epochs": 60,
        "patience": 60,
        "lr_patience": 60,
    }
    params = learner_params("place_cnn", changes)
    learner = get_learner("place_cnn")(params, seed=0)
    info = learner.fit(images, progress=False, places=places, traverses=traverses)
    return learner, info, params, (images, places, traverses)


def across_traverses(descriptors: np.ndarray, places: np.ndarray, traverses: np.ndarray) -> tuple[float, float]:
    """Mean distance between images of other traverses: of one place, and of different places."""
    distance = np.linalg.norm(descriptors[:, None] - descriptors[None], axis=-1)
    other_traverse = traverses[:, None] != traverses[None, :]
    same_place = places[:, None] == places[None, :]
    return float(distance[same_place & other_traverse].mean()), float(distance[~same_place & other_traverse].mean())


def test_training_brings_one_places_images_closer_than_other_places(trained):
    learner, info, params, (images, places, traverses) = trained
    # the training places: the fit held the others out for its validation
    held_out = validation_places(places, params["validation_fraction"], params["validation_block"], seed=0)
    kept = ~np.isin(places, held_out)
    images, places, traverses = images[kept], places[kept], traverses[kept]
    same, other = across_traverses(learner.describe(images), places, traverses)
    start = untrained(type(learner), params, (HEIGHT, WIDTH)).describe(images)
    same_before, other_before = across_traverses(start, places, traverses)
    # before training the change of traverse hides the place: its images no closer than others
    assert same_before > 0.9 * other_before
    assert same < 0.7 * other, (same, other, info["best_epoch"])
    recall, recall_before = (recall_across_traverses(d, places, traverses) for d in (learner.describe(images), start))
    assert recall > recall_before + 0.3, (recall, recall_before)


def test_the_same_seed_gives_the_same_model_bytes(trained, tmp_path):
    learner, _, params, (images, places, traverses) = trained
    again = get_learner("place_cnn")(params, seed=0)
    again.fit(images, progress=False, places=places, traverses=traverses)
    learner.save(tmp_path / "first")
    again.save(tmp_path / "second")
    for name in ("learner.json", "model.pt"):
        assert (tmp_path / "first" / name).read_bytes() == (tmp_path / "second" / name).read_bytes(), name


def test_a_strided_first_layer_replaces_the_first_pool_and_keeps_the_sizes_after_it():
    sizes = {}
    for downsampling in ("pool", "stride"):
        params = learner_params("place_cnn", {**TINY, "channels": [4, 8, 8], "first_downsampling": downsampling})
        model = untrained(get_learner("place_cnn"), params, (HEIGHT, WIDTH)).model
        pools = sum(isinstance(layer, torch.nn.MaxPool2d) for layer in model)
        first = next(layer for layer in model if isinstance(layer, torch.nn.Conv2d))
        # the activations entering the last convolution: the same grid either way
        convolutions = [index for index, layer in enumerate(model) if isinstance(layer, torch.nn.Conv2d)]
        with torch.no_grad():
            before_last = model[: convolutions[-1]](torch.zeros(1, 1, HEIGHT, WIDTH))
        sizes[downsampling] = (pools, first.stride, tuple(before_last.shape[2:]))
    assert sizes["pool"] == (2, (1, 1), (HEIGHT // 4, WIDTH // 4))
    assert sizes["stride"] == (1, (2, 2), (HEIGHT // 4, WIDTH // 4))


def test_a_strided_first_layer_needs_a_second_layer():
    with pytest.raises(
        ValueError, match=r"place_cnn\.first_downsampling = stride: .* place_cnn\.channels has one layer"
    ):
        get_learner("place_cnn")(
            learner_params("place_cnn", {**TINY, "channels": [4], "first_downsampling": "stride"}), seed=0
        )
