"""Tests for seasonloop.data.datasets (the split and augmented sets on disk) and augment's row layout."""

from __future__ import annotations

import json

import numpy as np
import pytest

from seasonloop.data import (
    datasets,  # its test_places / test_images, called through the module (pytest collects test_*)
)
from seasonloop.data.augment import augment_training_set, augmented_places
from seasonloop.data.datasets import dataset_record, read_split, training_images, training_places, write_augmented_sets
from seasonloop.io import save_array, write_json
from seasonloop.params.settings import AugmentConfig

SEASONS = ["summer", "winter"]
TRAIN, TEST = [0, 1, 2, 5], [8, 9]
CONFIG = AugmentConfig(copies=2, horizontal_flip=True, width_shift=0.3, height_shift=0.3, seed=7)


def constant_images(places, season_offset: int) -> np.ndarray:
    """(N, 4, 6) images, each filled with 10 * place + season_offset: flips and shifts keep the value."""
    return np.stack([np.full((4, 6), 10 * place + season_offset, np.uint8) for place in places])


@pytest.fixture
def split_dir(tmp_path):
    folder = tmp_path / "split"
    folder.mkdir()
    write_json(
        folder / "split.json",
        {"n_places": 12, "train": TRAIN, "test": TEST, "gap": [3, 4, 6, 7], "dropped_tunnel": [10], "dropped_stop": []},
    )
    for offset, season in enumerate(SEASONS):
        save_array(folder / f"{season}_train.npy", constant_images(TRAIN, offset))
        save_array(folder / f"{season}_test.npy", constant_images(TEST, offset))
    return folder


def test_augmented_places_describe_augment_training_set_rows():
    images = constant_images(TRAIN, 0)
    augmented = augment_training_set(images, 2, seed=0)
    np.testing.assert_array_equal(augmented[:, 0, 0] // 10, augmented_places(np.array(TRAIN), 2))
    np.testing.assert_array_equal(augmented_places(np.array(TRAIN), 0), TRAIN)
    with pytest.raises(ValueError, match="augment.copies"):
        augmented_places(np.array(TRAIN), -1)


def test_test_places_and_images(split_dir):
    np.testing.assert_array_equal(datasets.test_places(split_dir), TEST)
    images = datasets.test_images(split_dir, ["winter"])
    assert list(images) == ["winter"] and images["winter"].shape == (2, 4, 6)
    assert read_split(split_dir)["n_places"] == 12


def test_training_images_and_places_agree_row_by_row(split_dir, tmp_path):
    augmented_dir = tmp_path / "augmented"
    augmented_dir.mkdir()
    per_season = write_augmented_sets(split_dir, augmented_dir, SEASONS, CONFIG)
    assert per_season == {season: {"frames": 12, "train": 4, "train_augmented": 12, "test": 2} for season in SEASONS}
    for augmented, copies in ((augmented_dir, CONFIG.copies), (None, 0)):
        images = training_images(split_dir, augmented, SEASONS)
        places = training_places(split_dir, SEASONS, copies)
        assert len(images) == len(places) == len(TRAIN) * (copies + 1) * len(SEASONS)
        np.testing.assert_array_equal(images[:, 0, 0] // 10, places)
        # seasons in order: the first season's rows first
        half = len(images) // 2
        assert (images[:half, 0, 0] % 10 == 0).all() and (images[half:, 0, 0] % 10 == 1).all()
    # the same as the layout the stages used before: the train places tiled (copies + 1) per season
    np.testing.assert_array_equal(training_places(split_dir, SEASONS, 2), np.tile(TRAIN, 3 * len(SEASONS)))


def test_write_augmented_sets_is_augment_training_set_per_season(split_dir, tmp_path):
    write_augmented_sets(split_dir, tmp_path, SEASONS, CONFIG)
    for index, season in enumerate(SEASONS):
        train = np.load(split_dir / f"{season}_train.npy")
        expected = augment_training_set(train, 2, 7 + index, True, 0.3, 0.3)
        np.testing.assert_array_equal(np.load(tmp_path / f"{season}.npy"), expected)


def test_dataset_record():
    split = {"n_places": 12, "train": TRAIN, "test": TEST, "gap": [3, 4], "dropped_tunnel": [10], "dropped_stop": []}
    frames = {"place": "one frame", "frame_step": 1, "pairing": "by index", "alignment": {}, "offsets": {}}
    per_season = {season: {"frames": 12} for season in SEASONS}
    record = dataset_record(split, per_season, frames, {})
    assert list(record) == [
        "seasons",
        "total_images",
        "total_train",
        "total_test",
        "dropped_tunnel",
        "dropped_stop",
        "gap",
        "ground_truth",
        "place",
        "frame_step",
        "pairing",
        "alignment",
        "offsets",
    ]
    assert (record["total_images"], record["total_train"], record["total_test"]) == (24, 8, 4)
    assert (record["dropped_tunnel"], record["dropped_stop"], record["gap"]) == (1, 0, 2)
    detection = {"tunnel": {"recall": 1.0}}
    assert dataset_record(split, per_season, frames, detection)["detection"] == detection
    json.dumps(record)
