"""Seasons riding the built-in route at their own pace (SeasonRide): exact positions, own lengths."""

from __future__ import annotations

import copy
import json
from concurrent.futures import ProcessPoolExecutor as Executor
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from seasonloop.data import sources
from seasonloop.data.synthetic import (
    RideTimeline,
    RouteDifficulty,
    SeasonRide,
    SyntheticRoute,
    render_route,
    video,
    world,
)
from seasonloop.params.choices import RIDE_SCHEMA
from seasonloop.params.schema import check_params
from seasonloop.params.settings import SyntheticConfig

REPO = Path(__file__).resolve().parents[1]
W, H = 64, 36
SECONDS, SEED = 120, 0
# a short route that still has stops and tunnels: stops (13, 24), (39, 49); tunnels (67, 77), (93, 101)
BUSY = RouteDifficulty(
    tunnel_every_s=60,
    tunnel_min_s=6,
    tunnel_max_s=10,
    stop_every_s=60,
    stop_min_s=10,
    stop_max_s=15,
    event_gap_s=15,
    edge_margin_s=10,
    brake_time=5,
)
RIDE = SeasonRide(speed=1.6, stop_scale=2.0, start_s=5.0, swing=0.4)


@pytest.fixture(scope="module")
def route() -> SyntheticRoute:
    route = SyntheticRoute(SECONDS, SEED, BUSY)
    assert route.layout.stops and route.layout.tunnels
    return route


def read_positions(path: Path) -> np.ndarray:
    assert path.read_text().splitlines()[0] == "time_s,distance_m"
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def count_frames(path: Path) -> int:
    capture = cv2.VideoCapture(str(path))
    count = 0
    while capture.read()[0]:
        count += 1
    capture.release()
    return count


def test_the_default_ride_is_the_reference(route) -> None:
    clock = route.timeline("summer", SeasonRide())
    taus = np.arange(SECONDS * 4) / 4
    assert np.array_equal(clock.reference_time(taus), taus)
    assert clock.duration == SECONDS and clock.n_frames(2) == SECONDS * 2
    assert np.array_equal(route.ride_position("summer", SeasonRide(), taus), route.position(taus))
    assert clock.spans(route.layout.stops) == [list(map(float, span)) for span in route.layout.stops]
    for tau in (0.0, 15.5, 70.0):
        assert np.array_equal(route.ride_frame("winter", SeasonRide(), tau, W, H), route.frame("winter", tau, W, H))


def test_default_rides_render_todays_videos(tmp_path) -> None:
    seasons = ["summer", "winter"]
    render_route(tmp_path / "ref", seasons, 20, 2, W, H, 4, progress=False)
    rides = {season: SeasonRide() for season in seasons}
    render_route(tmp_path / "rides", seasons, 20, 2, W, H, 4, progress=False, rides=rides)
    for season in seasons:
        assert (tmp_path / "ref" / f"{season}.mp4").read_bytes() == (tmp_path / "rides" / f"{season}.mp4").read_bytes()
        ref = (tmp_path / "ref" / "positions" / f"{season}.csv").read_text()
        assert ref == (tmp_path / "rides" / "positions" / f"{season}.csv").read_text()
    assert not (tmp_path / "ref" / "rides.json").exists()


def test_render_workers_write_the_same_files_as_rendering_here(tmp_path, monkeypatch) -> None:
    rides = {"fall": SeasonRide(speed=1.25, start_s=3.0)}
    render_route(tmp_path / "here", ["summer", "fall"], 20, 2, W, H, 4, progress=False, rides=rides)
    # small chunks and a low threshold: two worker processes, several chunks each, uneven lengths
    monkeypatch.setattr(video, "_FRAMES_PER_WORKER", 10)
    monkeypatch.setattr(video, "_CHUNK_FRAMES", 7)
    monkeypatch.setattr(video, "_cores_for_workers", lambda: 2)
    started = []
    monkeypatch.setattr(video, "ProcessPoolExecutor", lambda *args, **kw: started.append(args) or Executor(*args, **kw))
    render_route(tmp_path / "workers", ["summer", "fall"], 20, 2, W, H, 4, progress=False, rides=rides)
    assert started and started[0][0] == 2
    files = sorted(path.relative_to(tmp_path / "here") for path in (tmp_path / "here").rglob("*") if path.is_file())
    assert len(files) == 6  # two videos, layout, rides and two positions
    for name in files:
        assert (tmp_path / "here" / name).read_bytes() == (tmp_path / "workers" / name).read_bytes(), name


def test_a_faster_season_has_fewer_frames_and_covers_the_same_route(tmp_path, route) -> None:
    rides = {"winter": SeasonRide(speed=2.0)}
    layout = render_route(tmp_path, ["summer", "winter"], SECONDS, 1, W, H, SEED, False, BUSY, rides)
    assert layout == route.layout
    summer, winter = (read_positions(tmp_path / "positions" / f"{s}.csv") for s in ("summer", "winter"))
    assert len(winter) < len(summer) == SECONDS
    for season, table in (("summer", summer), ("winter", winter)):
        assert count_frames(tmp_path / f"{season}.mp4") == len(table)
        assert np.array_equal(table[:, 0], np.arange(len(table)))  # time k/fps
        assert table[0, 1] == 0.0
        # the last frame is within one frame's travel of the end of the route
        assert route.length - 2.0 * 30.0 < table[-1, 1] <= route.length + 1e-3
    np.testing.assert_allclose(summer[:, 1], route.position(np.arange(SECONDS)), atol=1e-4)
    record = json.loads((tmp_path / "rides.json").read_text())
    assert record["fps"] == 1 and set(record["seasons"]) == {"summer", "winter"}
    assert record["seasons"]["winter"]["ride"] == {"speed": 2.0, "stop_scale": 1.0, "start_s": 0.0, "swing": 0.0}
    assert record["seasons"]["winter"]["frames"] == len(winter)
    assert record["seasons"]["summer"]["stops"] == [list(map(float, span)) for span in route.layout.stops]
    assert len(record["seasons"]["winter"]["tunnels"]) == len(route.layout.tunnels)


def test_positions_are_monotone_start_at_start_s_and_stand_during_stops(route) -> None:
    clock = route.timeline("fall", RIDE)
    taus = np.arange(clock.n_frames(20)) / 20
    positions = np.asarray(route.ride_position("fall", RIDE, taus))
    assert np.all(np.diff(positions) >= 0)
    assert positions[0] == route.position(RIDE.start_s)
    assert route.length - 1.0 < float(route.ride_position("fall", RIDE, clock.duration)) <= route.length + 1e-9
    for (a, b), (start, end) in zip(route.layout.stops, clock.spans(route.layout.stops)):
        assert start < end
        # the reference stands on [a - 1, b - 1]: inside the stop span until g reaches b - 1
        standing_until = clock.season_time(b - 1.0)
        assert start == round(clock.season_time(a), 3)
        assert standing_until - clock.season_time(a) == pytest.approx((b - 1 - a) * RIDE.stop_scale, abs=1e-9)
        inside = (taus >= clock.season_time(a)) & (taus <= standing_until)
        assert inside.sum() > 10 and np.all(positions[inside] == route.position(a))
        assert clock.rate(0.5 * (start + standing_until)) == 1.0 / RIDE.stop_scale


def test_a_ride_is_exact_between_the_reference_times(route) -> None:
    clock = route.timeline("spring", SeasonRide(speed=2.0))
    assert clock.reference_time(5.0) == 10.0  # before the first stop: g = start_s + speed * tau
    g = np.asarray(clock.reference_time(np.linspace(0.0, clock.duration, 500)))
    assert np.all(np.diff(g) > 0) and g[-1] == pytest.approx(SECONDS)
    for tau in (3.0, 40.0, clock.duration - 1.0):
        assert clock.season_time(float(clock.reference_time(tau))) == pytest.approx(tau, abs=1e-9)


def test_seasons_at_the_same_place_share_the_geometry(monkeypatch) -> None:
    route = SyntheticRoute(SECONDS, SEED, BUSY)
    calls: list[float] = []
    real = world.render_codes

    def counting(view, p, *args):
        calls.append(p)
        return real(view, p, *args)

    monkeypatch.setattr(world, "render_codes", counting)
    fast = SeasonRide(speed=2.0)
    route.ride_frame("summer", fast, 3.0, W, H)
    route.ride_frame("winter", fast, 3.0, W, H)
    route.frame("fall", 6.0, W, H)  # the reference at g(3) = 6: the same place
    route.ride_frame("spring", SeasonRide(start_s=6.0), 0.0, W, H)
    assert len(calls) == 1
    route.frame("fall", 50.0, W, H)
    assert len(calls) == 2
    again = SyntheticRoute(SECONDS, SEED, BUSY)
    assert np.array_equal(again.ride_frame("summer", RIDE, 33.3, W, H), route.ride_frame("summer", RIDE, 33.3, W, H))


def test_positions_are_removed_on_error(tmp_path, monkeypatch) -> None:
    (tmp_path / "keep.txt").write_text("not ours")

    def failing(self, fps):
        raise RuntimeError("record broke")

    # rides.json is written last: everything else, positions included, was there
    monkeypatch.setattr(RideTimeline, "to_json", failing)
    with pytest.raises(RuntimeError, match="record broke"):
        render_route(tmp_path, ["summer", "fall"], 20, 1, W, H, 0, progress=False, rides={"fall": RIDE})
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


@pytest.mark.parametrize(
    "field, value",
    [
        ("speed", 0.2),
        ("speed", 5.5),
        ("speed", "fast"),
        ("stop_scale", 0.0),
        ("stop_scale", 11),
        ("start_s", -1.0),
        ("swing", 0.9),
        ("swing", -0.1),
        ("swing", True),
        ("speed", float("nan")),
    ],
)
def test_invalid_rides_name_the_field(field, value) -> None:
    with pytest.raises(ValueError, match=f"^{field}: "):
        SeasonRide(**{field: value})


def test_a_ride_starting_too_late_is_refused_before_any_file(tmp_path) -> None:
    with pytest.raises(ValueError, match="start_s"):
        render_route(
            tmp_path / "out", ["summer"], 20, 1, W, H, 0, progress=False, rides={"summer": SeasonRide(start_s=15)}
        )
    with pytest.raises(ValueError, match="not rendered"):
        render_route(tmp_path / "out", ["summer"], 20, 1, W, H, 0, progress=False, rides={"winter": SeasonRide()})
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("field", list(RIDE_SCHEMA))
def test_the_schema_accepts_the_rides_the_code_accepts(field) -> None:
    for value in (-1.0, 0.0, 0.1, 0.2, 0.5, 0.9, 1.0, 5.0, 5.01, 10.0, 10.5):
        try:
            SeasonRide(**{field: value})
            code_ok = True
        except ValueError:
            code_ok = False
        try:
            RIDE_SCHEMA[field](f"synthetic.rides.summer.{field}", value)
            schema_ok = True
        except ValueError:
            schema_ok = False
        assert code_ok == schema_ok, (field, value)


@pytest.fixture
def params() -> dict:
    return yaml.safe_load((REPO / "params.yaml").read_text())


@pytest.mark.parametrize(
    "rides, message",
    [
        ({"summer": {"sped": 2}}, r"synthetic\.rides\.summer\.sped: unknown key \(known: speed, stop_scale"),
        ({"autumn": {}}, r"synthetic\.rides: unknown season 'autumn'"),
        ({"summer": {"speed": 9}}, r"synthetic\.rides\.summer\.speed: expected a number in \(0\.2, 5\]"),
        ({"summer": 2}, r"synthetic\.rides\.summer: expected a mapping"),
        ({"summer": {"start_s": 1795}}, r"synthetic\.rides\.summer\.start_s: 1795 leaves less than 10 s"),
    ],
)
def test_the_params_check_names_a_bad_ride(params, rides, message) -> None:
    bad = copy.deepcopy(params)
    bad["synthetic"]["rides"] = rides
    with pytest.raises(ValueError, match=message):
        check_params(bad, ["synthetic"])


def test_rides_from_params_reach_the_renderer(tmp_path, params) -> None:
    params["synthetic"].update(
        seconds=20, fps=1, width=W, height=H, rides={"winter": {"speed": 2}, "fall": {"swing": 0.3}}
    )
    synthetic = SyntheticConfig.from_params(params)
    assert synthetic.rides == {"winter": {"speed": 2}, "fall": {"swing": 0.3}}
    paths = sources._render_synthetic(tmp_path, ["summer", "winter"], None, synthetic)  # type: ignore[arg-type]
    assert set(paths) == {"summer", "winter"}
    record = json.loads((tmp_path / "rides.json").read_text())["seasons"]
    assert set(record) == {"summer", "winter"}  # fall is not rendered: its ride is not used
    assert record["winter"]["ride"]["speed"] == 2.0 and record["summer"]["ride"] == SeasonRide().to_json()
    assert len(read_positions(tmp_path / "positions" / "winter.csv")) == record["winter"]["frames"] < 20
