"""Tests for the synthetic Nordland-style route renderer (short routes, small frames)."""

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from seasonloop.data import synthetic
from seasonloop.data.synthetic import (
    SEASONS,
    RouteDifficulty,
    RouteLayout,
    SyntheticRoute,
    make_layout,
    render_frame,
    render_preview,
    render_route,
)
from seasonloop.params.settings import SyntheticConfig

W, H = 128, 72


@pytest.fixture(scope="module")
def route() -> SyntheticRoute:
    return SyntheticRoute(700, seed=3)


def gray(image: np.ndarray) -> np.ndarray:
    return cv2.cvtColor(image, cv2.COLOR_BGR2GRAY).astype(np.float32)


def moving_times(layout: RouteLayout, step: int) -> list[int]:
    """Seconds where the train moves in daylight at t-1, t and t+1."""
    busy = layout.in_tunnel() | layout.stopped()
    return [t for t in range(31, layout.seconds - 31, step) if not busy[t - 1 : t + 2].any()]


@pytest.mark.parametrize("seconds", [600, 700, 3600, 35768])
@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_layout_events_are_valid(seconds: int, seed: int) -> None:
    layout = make_layout(seconds, seed)
    assert layout.seconds == seconds
    assert len(layout.tunnels) >= 1 and len(layout.stops) >= 1
    spans = sorted(layout.tunnels + layout.stops)
    for start, end in spans:
        assert 30 <= start < end <= seconds - 30
    for (_, end), (start, _) in zip(spans[:-1], spans[1:]):
        assert end <= start, "events overlap"
    assert all(10 <= end - start <= 40 for start, end in layout.tunnels)
    assert all(20 <= end - start <= 60 for start, end in layout.stops)


def test_layout_density_and_determinism() -> None:
    long = make_layout(35768, 0)
    # About one tunnel per 600 s and one stop per 900 s.
    assert 35768 / 600 * 0.7 < len(long.tunnels) < 35768 / 600 * 1.3
    assert 35768 / 900 * 0.7 < len(long.stops) < 35768 / 900 * 1.3
    assert make_layout(3600, 5) == make_layout(3600, 5)
    assert make_layout(3600, 5) != make_layout(3600, 6)


def test_short_layout_and_bad_seconds() -> None:
    assert make_layout(50, 0) == RouteLayout(50, (), ())
    with pytest.raises(ValueError, match="seconds"):
        make_layout(0, 0)
    with pytest.raises(ValueError, match="seed"):
        make_layout(100, -1)


def test_layout_flags_and_json_round_trip() -> None:
    layout = make_layout(3600, 2)
    in_tunnel, stopped = layout.in_tunnel(), layout.stopped()
    assert in_tunnel.shape == stopped.shape == (3600,)
    assert in_tunnel.sum() == sum(end - start for start, end in layout.tunnels)
    assert stopped.sum() == sum(end - start for start, end in layout.stops)
    start, end = layout.tunnels[0]
    assert in_tunnel[start] and in_tunnel[end - 1] and not in_tunnel[start - 1] and not in_tunnel[end]
    data = json.loads(json.dumps(layout.to_json()))
    assert RouteLayout.from_json(data) == layout
    del data["stops"]
    with pytest.raises(ValueError, match="stops"):
        RouteLayout.from_json(data)


def test_position_stands_still_exactly_during_stops(route: SyntheticRoute) -> None:
    positions = route.position(np.arange(route.seconds))
    same_as_before = np.zeros(route.seconds, dtype=bool)
    same_as_before[1:] = positions[1:] == positions[:-1]
    np.testing.assert_array_equal(same_as_before, route.layout.stopped())
    assert np.all(np.diff(positions) >= 0)


def test_frames_are_deterministic_and_order_independent() -> None:
    first, second = SyntheticRoute(300, seed=11), SyntheticRoute(300, seed=11)
    times = [40.0, 40.5, 123.0]
    a = [first.frame(season, t, W, H) for t in times for season in SEASONS]
    # Render the other route in a different order: frames must not depend on it.
    b = {(season, t): second.frame(season, t, W, H) for season in reversed(SEASONS) for t in reversed(times)}
    for (t, season), image in zip([(t, s) for t in times for s in SEASONS], a):
        assert image.shape == (H, W, 3) and image.dtype == np.uint8
        np.testing.assert_array_equal(image, b[(season, t)])
    np.testing.assert_array_equal(render_frame(first, "fall", 40.0, W, H), b[("fall", 40.0)])
    other = SyntheticRoute(300, seed=12)
    assert np.abs(gray(other.frame("summer", 123.0, W, H)) - gray(a[8])).mean() > 10.0


def test_tunnel_frames_are_much_darker(route: SyntheticRoute) -> None:
    for season in SEASONS:
        tunnel_times = [t for start, end in route.layout.tunnels for t in range(start, end)]
        inside = [gray(route.frame(season, float(t), W, H)).mean() for t in tunnel_times]
        outside = [gray(route.frame(season, float(t), W, H)).mean() for t in moving_times(route.layout, 15)]
        assert np.mean(inside) < 0.35 * np.mean(outside), season
        assert np.max(inside) < np.median(outside)


def test_standing_frames_are_near_identical_moving_frames_are_not(route: SyntheticRoute) -> None:
    start, end = route.layout.stops[0]
    standing = [
        np.abs(gray(route.frame("summer", t, W, H)) - gray(route.frame("summer", t - 0.5, W, H))).mean()
        for t in np.arange(start + 1.0, end, 1.0)
    ]
    moving = [
        np.abs(gray(route.frame("summer", float(t), W, H)) - gray(route.frame("summer", t - 0.5, W, H))).mean()
        for t in moving_times(route.layout, 20)
    ]
    assert max(standing) < 3.0
    assert np.mean(moving) > 3.0 * np.mean(standing)


def test_seasons_differ_and_winter_is_hardest(route: SyntheticRoute) -> None:
    times = moving_times(route.layout, 12)
    frames = {season: [gray(route.frame(season, float(t), W, H)) for t in times] for season in SEASONS}
    contrast = {season: np.mean([f.std() for f in frames[season]]) for season in SEASONS}
    assert min(contrast, key=contrast.get) == "winter", contrast
    change = {
        season: np.mean([np.abs(a - b).mean() for a, b in zip(frames["summer"], frames[season])])
        for season in SEASONS[1:]
    }
    assert min(change.values()) > 8.0, change
    assert max(change, key=change.get) == "winter", change


def test_places_far_apart_differ_more_than_consecutive_seconds(route: SyntheticRoute) -> None:
    def small(t: float) -> np.ndarray:
        return cv2.resize(gray(route.frame("summer", t, W, H)), (32, 16), interpolation=cv2.INTER_AREA)

    times = [t for t in moving_times(route.layout, 9) if t + 20 < route.seconds - 30]
    consecutive = np.mean([np.abs(small(t) - small(t + 1.0)).mean() for t in times])
    far_apart = np.mean([np.abs(small(t) - small(t + 20.0)).mean() for t in times])
    assert far_apart > 2.0 * consecutive


def test_frame_rejects_bad_arguments(route: SyntheticRoute) -> None:
    with pytest.raises(ValueError, match="autumn"):
        route.frame("autumn", 1.0, W, H)
    with pytest.raises(ValueError, match="701"):
        route.frame("summer", 701.0, W, H)
    with pytest.raises(ValueError, match="width"):
        route.frame("summer", 1.0, 8, H)


def test_render_route_writes_readable_videos(tmp_path) -> None:
    out = tmp_path / "videos"
    layout = render_route(out, ["summer", "winter"], seconds=40, fps=2, width=W, height=H, seed=4, progress=False)
    assert layout == SyntheticRoute(40, 4).layout
    for season in ("summer", "winter"):
        capture = cv2.VideoCapture(str(out / f"{season}.mp4"))
        assert capture.isOpened()
        count = 0
        while True:
            ok, image = capture.read()
            if not ok:
                break
            assert image.shape == (H, W, 3)
            count += 1
        capture.release()
        assert count == 80
    assert RouteLayout.from_json(json.loads((out / "layout.json").read_text())) == layout
    assert sorted(p.name for p in out.iterdir()) == ["layout.json", "positions", "summer.mp4", "winter.mp4"]


def test_render_route_rejects_unknown_season(tmp_path) -> None:
    with pytest.raises(ValueError, match="autumn"):
        render_route(tmp_path / "out", ["summer", "autumn"], 20, 1, W, H, 0, progress=False)
    assert not (tmp_path / "out").exists()


def test_render_route_removes_partial_files_on_error(tmp_path, monkeypatch) -> None:
    real_frame = SyntheticRoute.frame

    def failing_frame(self, season, t, width, height):
        if t >= 5.0:
            raise RuntimeError("renderer broke")
        return real_frame(self, season, t, width, height)

    monkeypatch.setattr(synthetic.SyntheticRoute, "frame", failing_frame)
    (tmp_path / "keep.txt").write_text("not ours")
    with pytest.raises(RuntimeError, match="renderer broke"):
        render_route(tmp_path, ["summer", "fall"], 20, 2, W, H, 0, progress=False)
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


def test_render_preview_writes_png(tmp_path) -> None:
    path = tmp_path / "preview.png"
    render_preview(path, seconds=200, seed=1, times=[40.0, 100.0, 160.0], width=W, height=H)
    image = cv2.imread(str(path))
    assert image is not None
    # Three rows of places and four season columns, plus labels.
    assert image.shape[0] > 3 * H and image.shape[1] > 4 * W
    assert image.std() > 20.0


# --- difficulty knobs (params.yaml synthetic.*) ------------------------------------------------


def test_default_knobs_are_the_shipped_params() -> None:
    # the pipeline's route is the pinned one only while params.yaml holds the defaults
    params = yaml.safe_load((Path(__file__).resolve().parents[1] / "params.yaml").read_text())
    config = SyntheticConfig.from_params(params)
    assert RouteDifficulty(**{knob: getattr(config, knob) for knob in RouteDifficulty.knobs()}) == RouteDifficulty()
    assert set(RouteDifficulty.knobs()) <= set(SyntheticConfig.keys())


def test_a_higher_tunnel_rate_gives_more_tunnels_and_lengths_follow_the_knobs() -> None:
    busy = RouteDifficulty(tunnel_every_s=200.0, tunnel_min_s=12, tunnel_max_s=15, stop_every_s=3000.0)
    default = [make_layout(7200, seed) for seed in range(4)]
    changed = [make_layout(7200, seed, busy) for seed in range(4)]
    assert sum(len(lay.tunnels) for lay in changed) > 2 * sum(len(lay.tunnels) for lay in default)
    assert sum(len(lay.stops) for lay in changed) < sum(len(lay.stops) for lay in default)
    assert all(12 <= end - start <= 15 for lay in changed for start, end in lay.tunnels)


def test_gap_and_margin_knobs_are_kept() -> None:
    knobs = RouteDifficulty(event_gap_s=90, edge_margin_s=200, stop_min_s=5, stop_max_s=8)
    for seed in range(4):
        layout = make_layout(3600, seed, knobs)
        spans = sorted(layout.tunnels + layout.stops)
        assert spans and all(start >= 200 and end <= 3600 - 200 for start, end in spans)
        assert all(b[0] - a[1] >= 90 for a, b in zip(spans[:-1], spans[1:]))
        assert all(5 <= end - start <= 8 for start, end in layout.stops)


def test_a_faster_train_covers_more_distance_and_still_stands_at_stops() -> None:
    slow, fast = SyntheticRoute(700, 3), SyntheticRoute(700, 3, RouteDifficulty(cruise_speed=30.0))
    assert fast.layout == slow.layout
    assert fast.length > 1.3 * slow.length
    start, end = fast.layout.stops[0]
    assert fast.position(float(start)) == fast.position(float(end - 1))


def test_a_higher_winter_contrast_makes_winter_easier(route: SyntheticRoute) -> None:
    easier = SyntheticRoute(700, 3, RouteDifficulty(winter_contrast=1.0, winter_shading=1.0))
    times = moving_times(route.layout, 60)
    for t in times:
        # only winter's light changes: same geometry, same summer
        assert np.array_equal(easier.frame("summer", float(t), W, H), route.frame("summer", float(t), W, H))
    hard = np.mean([gray(route.frame("winter", float(t), W, H)).std() for t in times])
    easy = np.mean([gray(easier.frame("winter", float(t), W, H)).std() for t in times])
    assert easy > 1.5 * hard, (easy, hard)


@pytest.mark.parametrize(
    "knobs, message",
    [
        ({"tunnel_min_s": 30, "tunnel_max_s": 20}, "tunnel_max_s: 20 is below tunnel_min_s 30"),
        ({"stop_min_s": 2.5}, "stop_min_s: expected an integer"),
        ({"cruise_speed": 0.0}, "cruise_speed: expected a positive number"),
        ({"event_gap_s": -1}, "event_gap_s: expected a number >= 0"),
    ],
)
def test_bad_knobs_are_rejected(knobs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        RouteDifficulty(**knobs)
