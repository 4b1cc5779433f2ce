import numpy as np
import pytest

from seasonloop.data.alignment import apply_offsets, check_alignment, measure_offset
from seasonloop.data.preprocess import to_gray
from seasonloop.data.synthetic import SyntheticRoute


def route_frames(season, seconds=160, seed=1):
    route = SyntheticRoute(seconds, seed)
    return to_gray(np.stack([route.frame(season, float(t), 64, 36) for t in range(seconds)]), 16, 32)


@pytest.fixture(scope="module")
def seasons():
    return {season: route_frames(season) for season in ("summer", "winter", "fall")}


def test_aligned_seasons_measure_no_offset(seasons):
    for other in ("fall", "winter"):
        alignment = measure_offset(seasons["summer"], seasons[other], max_offset=8)
        assert not alignment.clear, (other, alignment)
        assert alignment.n_sampled > 100


def test_a_shifted_season_is_found(seasons):
    # fall starts 5 places late: its place i is the route's place i + 5
    shifted = seasons["fall"][5:]
    alignment = measure_offset(seasons["summer"][:-5], shifted, max_offset=8)
    assert alignment.offset == -5 and alignment.clear
    alignment = measure_offset(seasons["summer"][5:], seasons["fall"][:-5], max_offset=8)
    assert alignment.offset == 5 and alignment.clear


def test_offsets_drop_leading_places_and_cut_to_one_length():
    kept = apply_offsets({"summer": 100, "winter": 100}, {"winter": 7})
    assert kept == {"summer": slice(0, 93), "winter": slice(7, 100)}
    with pytest.raises(ValueError, match="data.offsets.winter"):
        apply_offsets({"summer": 10, "winter": 10}, {"winter": 10})


def test_the_check_stops_on_a_clear_offset_with_one_line():
    route = SyntheticRoute(160, 2)
    colour = {
        season: np.stack([route.frame(season, float(t), 64, 36) for t in range(160)]) for season in ("summer", "winter")
    }
    result = check_alignment(colour, max_offset=8, stop_threshold=1.0)
    assert set(result) == {"summer-winter"} and result["summer-winter"]["clear"] is False
    late = {"summer": colour["summer"][:-6], "winter": colour["winter"][6:]}
    with pytest.raises(
        ValueError,
        match=r"winter vs summer: the frames match best at an offset of -6 places .*data\.offsets\.summer: 6",
    ):
        check_alignment(late, max_offset=8, stop_threshold=1.0)
    assert check_alignment(late, max_offset=0, stop_threshold=1.0) == {}


def standing_route(season, lag, places=100, stop=(5, 80)):
    """A route where the train stands from place stop[0] to stop[1] while a faint shade passes the
    window one pixel a place (people, another train), `lag` places later in this season: inside
    the stop every offset shows the same view and the shade's lag wins (real Nordland's stops
    behave so: summer and winter frames seconds 5,010-5,600 read as an offset of -10)."""
    route = SyntheticRoute(200, 1)
    frames = []
    for t in range(places):
        at = t if t < stop[0] else stop[0] if t < stop[1] else t - (stop[1] - stop[0])
        frame = route.frame(season, float(at), 64, 36).astype(np.int16)
        if stop[0] <= t < stop[1]:
            x = (t - lag) % 64
            frame[:, x : x + 4] -= 15
        frames.append(np.clip(frame, 0, 255).astype(np.uint8))
    return np.stack(frames)


def test_places_where_the_train_stands_are_left_out_of_the_sample():
    colour = {"summer": standing_route("summer", 0), "winter": standing_route("winter", 8)}
    # every place sampled: the stop's shade reads as a clear offset of 8 places
    with pytest.raises(ValueError, match="offset of 8 places"):
        check_alignment(colour, max_offset=10, stop_threshold=0.0)
    # the stop left out (split.stop_threshold's test): too few moving places for a verdict
    result = check_alignment(colour, max_offset=10, stop_threshold=1.0)["summer-winter"]
    assert result["clear"] is False and result["n_sampled"] < 20
    # a longer route with the same stop: enough moving places, aligned
    colour = {season: standing_route(season, lag, 160, (40, 110)) for season, lag in (("summer", 0), ("winter", 8))}
    result = check_alignment(colour, max_offset=10, stop_threshold=1.0)["summer-winter"]
    assert result["offset"] == 0 and result["n_sampled"] >= 20
