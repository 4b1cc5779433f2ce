"""Tests for seasonloop.evaluation.sequence (SeqSLAM)."""

import numpy as np
import pytest

from seasonloop.evaluation.sequence import enhance_distance_contrast, enhancement_windows, sequence_distances


def reference_enhance(distances: np.ndarray, window: int, database_places=None) -> np.ndarray:
    """Loop version: z-score over windows of +-window//2 columns clipped at the edges and at
    breaks in the database places, then shift min to 0."""
    half = window // 2
    segment = segments(np.arange(distances.shape[1]) if database_places is None else database_places)
    out = np.zeros(distances.shape)
    for i in range(distances.shape[0]):
        for j in range(distances.shape[1]):
            columns = [
                c for c in range(max(0, j - half), j + half + 1) if c < len(segment) and segment[c] == segment[j]
            ]
            values = distances[i, columns]
            if values.std() > 0:
                out[i, j] = (distances[i, j] - values.mean()) / values.std()
    return out - out.min()


def segments(places):
    """Segment number per row: a new segment wherever a place id is not the previous one + 1."""
    return np.cumsum(np.concatenate(([1], np.diff(places) != 1)))


def reference_sequence(distances, length, velocities, window, query_places=None, database_places=None):
    """Loop version of the trailing-trajectory score; a trajectory stays inside one query segment
    (shorter near its start) and one database segment (else disqualified)."""
    enhanced = reference_enhance(distances, window, database_places)
    n_queries, n_database = enhanced.shape
    query_segment = segments(np.arange(n_queries) if query_places is None else query_places)
    database_segment = segments(np.arange(n_database) if database_places is None else database_places)
    best = np.full(enhanced.shape, np.inf)
    for i in range(n_queries):
        for j in range(n_database):
            for velocity in velocities:
                points = [
                    (i - k, j - int(np.floor(velocity * k + 0.5)))
                    for k in range(length)
                    if i - k >= 0 and query_segment[i - k] == query_segment[i]
                ]
                if all(
                    0 <= column < n_database and database_segment[column] == database_segment[j] for _, column in points
                ):
                    best[i, j] = min(best[i, j], np.mean([enhanced[row, column] for row, column in points]))
    return best


def noisy_diagonal(size: int, depth: float, seed: int) -> np.ndarray:
    """Unit-variance noise around 1 with the true-match diagonal lowered by depth."""
    rng = np.random.default_rng(seed)
    distances = 1.0 + rng.normal(size=(size, size))
    distances[np.arange(size), np.arange(size)] -= depth
    return distances - distances.min()


def test_enhance_distance_contrast_matches_loop_reference():
    rng = np.random.default_rng(0)
    distances = rng.random((6, 17)) * 3.0 + 100.0  # offset: checks the cumulative sums stay precise
    np.testing.assert_allclose(
        enhance_distance_contrast(distances, window=6), reference_enhance(distances, 6), atol=1e-5
    )


def test_enhance_distance_contrast_constant_rows_are_finite():
    distances = np.vstack([np.full(10, 0.5), np.arange(10.0)])
    enhanced = enhance_distance_contrast(distances, window=4)
    assert np.isfinite(enhanced).all()
    assert enhanced.min() == 0.0
    assert np.ptp(enhanced[0]) == 0.0


def test_sequence_distances_matches_loop_reference():
    rng = np.random.default_rng(1)
    distances = rng.random((12, 15))
    velocities = np.linspace(0.5, 1.5, 3)
    expected = reference_sequence(distances, length=4, velocities=velocities, window=4)
    result = sequence_distances(distances, length=4, v_min=0.5, v_max=1.5, v_steps=3, window=4)
    assert result.shape == (12, 15) and result.dtype == np.float32
    np.testing.assert_array_equal(np.isinf(result), np.isinf(expected))
    finite = np.isfinite(expected)
    np.testing.assert_allclose(result[finite], expected[finite], atol=1e-5)


# Hand-made place ids: test blocks and dropped tunnel/stop places leave gaps.
QUERY_PLACES = np.array([0, 1, 2, 3, 10, 11, 12, 13, 14, 30, 31, 32])
DATABASE_PLACES = np.array([5, 6, 7, 8, 9, 20, 21, 22, 23, 24, 25, 40, 41, 42, 43])


@pytest.mark.parametrize("v_min, v_max", [(0.5, 1.5), (-1.0, 1.0)])
def test_sequence_never_crosses_a_break_in_place_ids(v_min, v_max):
    rng = np.random.default_rng(5)
    distances = rng.random((12, 15))
    velocities = np.linspace(v_min, v_max, 3)
    expected = reference_sequence(distances, 4, velocities, 4, QUERY_PLACES, DATABASE_PLACES)
    result = sequence_distances(
        distances,
        length=4,
        v_min=v_min,
        v_max=v_max,
        v_steps=3,
        window=4,
        query_places=QUERY_PLACES,
        database_places=DATABASE_PLACES,
    )
    np.testing.assert_array_equal(np.isinf(result), np.isinf(expected))
    finite = np.isfinite(expected)
    np.testing.assert_allclose(result[finite], expected[finite], atol=1e-5)
    # Ignoring the breaks gives other scores: the rule changes the result.
    assert not np.allclose(result[finite], sequence_distances(distances, 4, v_min, v_max, 3, 4)[finite])


def test_sequence_restarts_at_a_break():
    rng = np.random.default_rng(6)
    distances = rng.random((12, 15))
    enhanced = enhance_distance_contrast(distances, window=4, database_places=DATABASE_PLACES)
    result = sequence_distances(
        distances,
        length=4,
        v_min=1.0,
        v_max=1.0,
        v_steps=1,
        window=4,
        query_places=QUERY_PLACES,
        database_places=DATABASE_PLACES,
    )
    # Query row 4 (place 10) starts a segment: its sequence is that one point, so at database
    # column 5 (place 20, a segment start too) the score is the enhanced difference itself ...
    assert result[4, 5] == pytest.approx(enhanced[4, 5], abs=1e-6)
    # ... and row 5 (place 11) averages two points, staying in both segments.
    assert result[5, 6] == pytest.approx((enhanced[5, 6] + enhanced[4, 5]) / 2, abs=1e-6)
    # Contiguous place ids are the same as giving none.
    contiguous = np.arange(12)
    np.testing.assert_array_equal(
        sequence_distances(distances, 4, query_places=contiguous, database_places=np.arange(15)),
        sequence_distances(distances, 4),
    )
    with pytest.raises(ValueError, match="query_places"):
        sequence_distances(distances, 4, query_places=contiguous[:5])


def test_sequence_recovers_weak_diagonal():
    size = 200
    distances = noisy_diagonal(size, depth=2.0, seed=0)
    truth = np.arange(size)
    single_fraction = np.mean(distances.argmin(axis=1) == truth)
    sequence_fraction = np.mean(sequence_distances(distances).argmin(axis=1) == truth)
    assert single_fraction < 0.5
    assert sequence_fraction > 0.9


def test_sequence_recovers_weak_diagonal_single_velocity():
    size = 200
    distances = noisy_diagonal(size, depth=2.0, seed=2)
    truth = np.arange(size)
    assert np.mean(distances.argmin(axis=1) == truth) < 0.5
    scores = sequence_distances(distances, length=10, v_min=1.0, v_max=1.0, v_steps=1)
    assert np.mean(scores.argmin(axis=1) == truth) > 0.9


def test_sequence_length_one_is_enhanced_matrix():
    rng = np.random.default_rng(3)
    distances = rng.random((5, 8))
    np.testing.assert_allclose(sequence_distances(distances, length=1), enhance_distance_contrast(distances), atol=1e-6)


def test_sequence_bad_inputs_raise():
    distances = np.random.default_rng(4).random((10, 10))
    with pytest.raises(ValueError, match="too short"):
        sequence_distances(distances[:, :3], length=10)
    with pytest.raises(ValueError, match="length"):
        sequence_distances(distances, length=0)
    with pytest.raises(ValueError, match="v_min"):
        sequence_distances(distances, v_min=1.5, v_max=1.0)
    with pytest.raises(ValueError, match="window"):
        enhance_distance_contrast(distances, window=1)
    with pytest.raises(ValueError, match="NaN"):
        enhance_distance_contrast(np.full((2, 2), np.nan))


def test_contrast_enhancement_windows_stop_at_breaks_in_the_database():
    # two test blocks far apart on the route: changing the second must not move the first's
    # enhanced columns (up to the one uniform shift that keeps the matrix non-negative)
    rng = np.random.default_rng(3)
    places = np.concatenate([np.arange(0, 12), np.arange(300, 312)])
    distances = rng.random((5, places.size))
    changed = distances.copy()
    changed[:, 12:] = 10 * rng.random((5, 12))
    first = enhance_distance_contrast(distances, 6, places)[:, :12]
    again = enhance_distance_contrast(changed, 6, places)[:, :12]
    offset = first - again
    np.testing.assert_allclose(offset, offset.flat[0], atol=1e-5)
    # the first block alone gives the same columns, up to that shift
    alone = enhance_distance_contrast(distances[:, :12], 6, places[:12])
    np.testing.assert_allclose(first - alone, (first - alone).flat[0], atol=1e-5)
    # without the places the windows cross the break and the first block moves
    crossing = enhance_distance_contrast(distances, 6)[:, :12] - enhance_distance_contrast(changed, 6)[:, :12]
    assert np.ptp(crossing) > 1e-2


def test_the_three_window_rules_at_a_break():
    # database segments: places 0-4, 10-11 (a 2-place fragment), 20-29; window 4 (half 2)
    places = np.r_[np.arange(5), 10, 11, np.arange(20, 30)]
    ignore = enhancement_windows(len(places), 4, places, "ignore")
    clip = enhancement_windows(len(places), 4, places, "clip")
    shift = enhancement_windows(len(places), 4, places, "shift")
    assert (ignore[0][5], ignore[1][5]) == (3, 8)  # across both breaks, as OpenSeqSLAM
    assert (ignore[0][0], ignore[1][0]) == (0, 3)  # clipped at the database's start
    assert (clip[0][5], clip[1][5]) == (5, 7) and (clip[0][7], clip[1][7]) == (7, 10)
    assert (shift[0][5], shift[1][5]) == (5, 7)  # the whole 2-place fragment
    assert (shift[0][7], shift[1][7]) == (7, 12) and (shift[0][16], shift[1][16]) == (12, 17)
    assert ((shift[1] - shift[0])[places >= 20] == 5).all()  # a fixed size inside the segment
    with pytest.raises(ValueError, match="sequence.window_at_breaks: expected one of ignore, shift, clip"):
        enhancement_windows(len(places), 4, places, "wrap")


def test_a_two_place_fragment_enhances_to_plus_minus_one_only_when_windows_stop_at_breaks():
    # the case: [0.10, 0.95] and [0.90, 0.91] give the same values inside the fragment
    places = np.r_[np.arange(6), 10, 11, np.arange(20, 26)]
    rows = np.random.default_rng(2).random((2, 14)) + 1.0
    rows[0, 6:8], rows[1, 6:8] = [0.10, 0.95], [0.90, 0.91]
    clipped = enhance_distance_contrast(rows, window=4, database_places=places, window_at_breaks="clip")
    # -1 and +1 in both rows (then one shift for the whole matrix)
    assert np.diff(clipped[:, 6:8], axis=1).ravel() == pytest.approx([2.0, 2.0], abs=1e-5)
    ignored = enhance_distance_contrast(rows, window=4, database_places=places, window_at_breaks="ignore")
    assert not np.allclose(np.diff(ignored[0, 6:8]), np.diff(ignored[1, 6:8]), atol=1e-3)
