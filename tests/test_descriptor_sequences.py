"""The sequence descriptors beside SeqSLAM (seasonloop.evaluation.descriptor_sequences): seqNet's
windows and weights, breaks respected, and routes whose frames change in a known way."""

from __future__ import annotations

import numpy as np
import pytest
from sequence_settings import sequence_config

from seasonloop.data.ground_truth import aligned_truth
from seasonloop.evaluation.blocks import evaluate_descriptors
from seasonloop.evaluation.descriptor_sequences import delta_descriptors, sequence_windows, smoothed_descriptors
from seasonloop.params.settings import EvaluateConfig, SequenceConfig

EVALUATE = EvaluateConfig(("a-b",), "cosine", (), "distance", 0, 0, 10.0, ("single", "delta", "smoothed"))


def sequence_of(length: int, at_breaks: str = "shift") -> SequenceConfig:
    return sequence_config(length=length, window_at_breaks="ignore", descriptor_window_at_breaks=at_breaks)


def seqnet_window(index: int, length: int, first: int, stop: int) -> np.ndarray:
    """oravus/seqNet datasets.py getSeqInds: `length` rows around `index` inside [first, stop)."""
    rows = np.arange(max(first, index - length // 2), min(index + length - length // 2, stop))
    missing = length - len(rows)
    if rows[0] == first:
        rows = np.concatenate([rows, np.arange(rows[-1] + 1, rows[-1] + 1 + missing)])
    elif missing > 0 and rows[-1] == stop - 1:
        rows = np.concatenate([np.arange(rows[0] - missing, rows[0]), rows])
    return rows


def seqnet_delta(window: np.ndarray) -> np.ndarray:
    """oravus/seqNet seqNet.py Delta, then L2Norm: weights -1/(L/2) on the first L//2 rows, +1/(L/2) after."""
    weight = np.ones(len(window)) / (len(window) / 2.0)
    weight[: len(window) // 2] *= -1
    delta = window.T @ weight
    return delta / np.linalg.norm(delta)


def test_clipped_windows_are_seqnets_clipped_at_each_break():
    # place ids with two breaks: segments of 12, 7 and 3 rows
    places = np.concatenate([np.arange(12), np.arange(20, 27), np.arange(40, 43)])
    start, size = sequence_windows(places, 5, "clip")
    bounds = [(0, 12)] * 12 + [(12, 19)] * 7 + [(19, 22)] * 3
    for row, (first, stop) in enumerate(bounds):
        rows = np.arange(start[row], start[row] + size[row])
        # seqNet's centred window (2 before, 2 after), clipped to the segment: never across a break
        np.testing.assert_array_equal(rows, np.arange(max(first, row - 2), min(stop, row + 3)), str(row))
        if first + 2 <= row < stop - 2:  # away from a break: exactly seqNet's
            np.testing.assert_array_equal(rows, seqnet_window(row, 5, first, stop))
    # every row its own window where its segment is longer than the window (the 3-row one is one window)
    assert len(set(zip(start[:19].tolist(), size[:19].tolist()))) == 19


@pytest.mark.parametrize("length", [2, 6, 10])
def test_clipped_delta_and_smoothed_are_seqnets_away_from_breaks(length):
    rng = np.random.default_rng(length)
    descriptors = rng.normal(size=(30, 6)).astype(np.float32)
    places = np.arange(30)
    delta, smoothed = (
        delta_descriptors(descriptors, places, length, "clip"),
        smoothed_descriptors(descriptors, places, length, "clip"),
    )
    for row in range(length // 2, 30 - length + length // 2 + 1):  # windows away from the route's ends
        window = descriptors[seqnet_window(row, length, 0, 30)].astype(np.float64)
        np.testing.assert_allclose(delta[row], seqnet_delta(window), rtol=1e-5, atol=1e-6)
        mean = window.mean(axis=0)
        np.testing.assert_allclose(smoothed[row], mean / np.linalg.norm(mean), rtol=1e-5, atol=1e-6)
    assert delta.dtype == smoothed.dtype == np.float32


def test_a_steady_change_gives_one_delta_and_a_moving_mean():
    # each frame's descriptor drifts by the same step: the change over any window is that step
    start, step = np.array([1.0, 2.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0, -1.0])
    descriptors = start + np.arange(20)[:, None] * step
    delta = delta_descriptors(descriptors, np.arange(20), 6, "clip")
    # every window, the clipped ones at the route's ends too (odd lengths: the halves' means)
    np.testing.assert_allclose(delta, np.tile(step / np.linalg.norm(step), (20, 1)), atol=1e-6)
    # the mean of a window centred on frame t (6 frames: t-3 .. t+2) is the frame at t - 0.5
    smoothed = smoothed_descriptors(descriptors, np.arange(20), 6, "clip")
    centre = start + 9.5 * step
    np.testing.assert_allclose(smoothed[10], centre / np.linalg.norm(centre), atol=1e-6)


@pytest.mark.parametrize("at_breaks", ["shift", "clip"])
def test_a_window_never_reads_the_other_side_of_a_break(at_breaks):
    descriptors = np.ones((10, 3))
    descriptors[5:] = [-1.0, 5.0, 2.0]  # after the break, something else entirely
    places = np.array([0, 1, 2, 3, 4, 50, 51, 52, 53, 54])
    smoothed = smoothed_descriptors(descriptors, places, 10, at_breaks)
    np.testing.assert_allclose(smoothed[:5], np.full((5, 3), 1 / np.sqrt(3)), atol=1e-6)
    # no change within a steady stretch
    assert not delta_descriptors(descriptors, places, 10, at_breaks)[:5].any()


@pytest.mark.parametrize("at_breaks", ["shift", "clip"])
def test_a_place_alone_between_two_breaks_has_no_change_to_measure(at_breaks):
    alone = delta_descriptors(np.arange(6.0).reshape(3, 2), np.array([0, 5, 9]), 4, at_breaks)
    assert not alone.any()


@pytest.mark.parametrize(("at_breaks", "least"), [("clip", 0.9), ("shift", 0.8)])
def test_sequences_tell_apart_places_that_look_alike(at_breaks, least):
    # a route of 60 places where every place looks like one of 10 (single images cannot tell the
    # ~6 places of a look apart) but no 6 consecutive places hold the same looks; the query ride
    # sees them noisily
    rng = np.random.default_rng(0)
    looks = rng.normal(size=(10, 16))
    order = rng.integers(0, 10, 60)
    database = looks[order] + 0.01 * rng.normal(size=(60, 16))
    queries = looks[order] + 0.3 * rng.normal(size=(60, 16))
    places = np.arange(60)
    truth = aligned_truth(places, places, 0)
    sequence = sequence_of(6, at_breaks)
    fraction = {
        matcher: evaluate_descriptors(database, queries, truth, matcher, EVALUATE, sequence).metrics["fraction_correct"]
        for matcher in ("single", "delta", "smoothed")
    }
    # single images: about one in six (the look's places); sequences nearly all, but seqNet's
    # shifted windows give the route's first 4 and last 3 places one window each (5 can't be right)
    assert fraction["single"] < 0.3 and fraction["smoothed"] > least and fraction["delta"] > least, fraction


def test_the_delta_matcher_matches_delta_descriptors_by_the_metric():
    rng = np.random.default_rng(1)
    database, queries = rng.normal(size=(40, 8)), rng.normal(size=(25, 8))
    truth = aligned_truth(np.arange(40), np.arange(10, 35), 1)
    evaluation = evaluate_descriptors(database, queries, truth, "delta", EVALUATE, sequence_of(4))
    expected = (
        delta_descriptors(queries, np.arange(10, 35), 4, "shift")
        @ delta_descriptors(database, np.arange(40), 4, "shift").T
    )
    best = np.argmax(expected, axis=1)
    np.testing.assert_array_equal(evaluation.outcomes.correct, np.abs(best - np.arange(10, 35)) <= 1)


SEGMENTS = np.concatenate([np.arange(26), np.arange(30, 56), np.arange(70, 82), np.arange(100, 126)])


def seqnet_rows(places: np.ndarray, length: int) -> list[np.ndarray]:
    """Each row's window by seqNet's getSeqInds inside its run of consecutive place ids."""
    starts = np.flatnonzero(np.diff(places, prepend=places[0] - 2) != 1)
    stops = np.append(starts[1:], len(places))
    return [seqnet_window(row, length, first, stop) for first, stop in zip(starts, stops) for row in range(first, stop)]


@pytest.mark.parametrize("length", [2, 5, 10, 11])
def test_every_row_is_seqnets_under_shift_ends_of_segments_included(length):
    # segments of 26, 26, 12 and 26 places (the every-place route's test blocks are about 26): every
    # row's window, Delta and smoothed descriptor is seqNet's, the rows at each break included
    rng = np.random.default_rng(length)
    descriptors = rng.normal(size=(len(SEGMENTS), 7))
    windows = seqnet_rows(SEGMENTS, length)
    start, size = sequence_windows(SEGMENTS, length, "shift")
    delta = delta_descriptors(descriptors.astype(np.float32), SEGMENTS, length, "shift")
    smoothed = smoothed_descriptors(descriptors.astype(np.float32), SEGMENTS, length, "shift")
    for row, window in enumerate(windows):
        np.testing.assert_array_equal(np.arange(start[row], start[row] + size[row]), window, str(row))
        np.testing.assert_allclose(delta[row], seqnet_delta(descriptors[window]), rtol=1e-4, atol=1e-5)
        mean = descriptors[window].mean(axis=0)
        np.testing.assert_allclose(smoothed[row], mean / np.linalg.norm(mean), rtol=1e-4, atol=1e-5)
    # the clipped rule differs from seqNet's at the breaks only
    clipped = sequence_windows(SEGMENTS, length, "clip")
    differs = (clipped[0] != start) | (clipped[1] != size)
    assert differs.any() == (length > 1) and not differs[length : 26 - length].any()


def test_a_segment_shorter_than_the_window_is_one_window_under_shift():
    # seqNet never meets one (its sequences are whole traverses): the whole segment is the window
    places = np.array([0, 1, 2, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19])
    start, size = sequence_windows(places, 5, "shift")
    np.testing.assert_array_equal(start[:3], 0)
    np.testing.assert_array_equal(size[:3], 3)


def test_an_unknown_rule_at_breaks_is_refused_by_its_key():
    with pytest.raises(ValueError, match=r"^sequence.descriptor_window_at_breaks: expected one of shift, clip"):
        sequence_windows(np.arange(5), 3, "pad")
