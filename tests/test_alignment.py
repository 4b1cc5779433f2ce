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
    result = check_alignment(colour, max_offset=8)
    assert set(result) == {"summer-winter"} and result["summer-winter"]["clear"] is False
    late = {"summer": colour["summer"][:-6], "winter": colour["winter"][6:]}
    with pytest.raises(
        ValueError,
        match=r"winter vs summer: the frames match best at an offset of -6 places .*data\.offsets\.summer: 6",
    ):
        check_alignment(late, max_offset=8)
    assert check_alignment(late, max_offset=0) == {}
