"""Tests for the split's stage logic in seasonloop.data.split: the split from frame statistics, the
split folder written, and tunnel / stop detection scored against the truth."""

from __future__ import annotations

import json

import numpy as np
import pytest

from seasonloop.data.split import (
    detection_record,
    detection_scores,
    make_split,
    place_seconds,
    split_route,
    write_split_sets,
)
from seasonloop.params.settings import SplitConfig

CONFIG = SplitConfig(
    section_length=10, test_fraction=0.3, gap=1, folds=1, dark_threshold=40, stop_threshold=1.0, test_every={}
)


def stats_of(n: int) -> dict[str, np.ndarray]:
    brightness = np.full(n, 100.0)
    brightness[9] = 10  # a tunnel in one season only
    change = np.full(n, 5.0)
    change[18] = 0.5
    return {
        "summer_brightness": brightness,
        "summer_change": change,
        "winter_brightness": np.full(n, 90.0),
        "winter_change": np.full(n, 4.0),
    }


def test_split_route_is_make_split_of_the_detected_masks():
    split, tunnel, stop = split_route(stats_of(20), ["summer", "winter"], CONFIG)
    assert np.flatnonzero(tunnel).tolist() == [9] and np.flatnonzero(stop).tolist() == [18]
    expected = make_split(20, 10, 0.3, 1, tunnel, stop)
    assert split.to_json() == expected.to_json()
    assert split.dropped_tunnel.tolist() == [9] and split.dropped_stop.tolist() == [18]


def test_write_split_sets(tmp_path):
    split, _, _ = split_route(stats_of(20), ["summer"], CONFIG)
    images = np.arange(20 * 2 * 3, dtype=np.uint8).reshape(20, 2, 3)
    np.save(tmp_path / "summer.npy", images)
    out = tmp_path / "split"
    out.mkdir()
    write_split_sets(tmp_path, out, ["summer"], split)
    np.testing.assert_array_equal(np.load(out / "summer_train.npy"), images[split.train])
    np.testing.assert_array_equal(np.load(out / "summer_test.npy"), images[split.test])
    assert json.loads((out / "split.json").read_text()) == split.to_json()


def test_place_seconds():
    assert place_seconds(5, 1, 1.0).tolist() == [0, 1, 2, 3, 4]
    # every third sample at 2 samples per second: 0, 1.5, 3, 4.5 s, truncated
    assert place_seconds(4, 3, 2).tolist() == [0, 1, 3, 4]


def test_detection_scores():
    found = np.array([True, True, False, False])
    truth = np.array([True, False, True, False])
    assert detection_scores(found, truth) == {"true": 2, "found": 2, "recall": 0.5, "precision": 0.5}
    # nothing true and nothing found: no division by zero
    none = np.zeros(4, bool)
    assert detection_scores(none, none) == {"true": 0, "found": 0, "recall": 0.0, "precision": 0.0}


def test_detection_record_counts_a_dark_stop_as_a_tunnel():
    tunnel = np.array([True, False, False])
    stop = np.array([True, True, False])
    seconds = np.array([0, 2, 4])
    true_tunnel = np.array([1, 0, 0, 0, 0], bool)
    true_stop = np.array([0, 0, 1, 0, 1], bool)
    record = detection_record(tunnel, stop, true_tunnel, true_stop, seconds)
    assert list(record) == ["tunnel", "stop"]
    assert record["tunnel"] == {"true": 1, "found": 1, "recall": 1.0, "precision": 1.0}
    # place 0's stop is a tunnel: only place 1 is a found stop; true stops at places 1 and 2
    assert record["stop"] == {"true": 2, "found": 1, "recall": 0.5, "precision": 1.0}
    with pytest.raises(IndexError):
        detection_record(tunnel, stop, true_tunnel[:2], true_stop, seconds)
