"""Rendered frames pinned by exact pixels (SHA-256 of the uint8 BGR bytes).

The built-in route is the default data of every result: a change to the renderer that moves one
pixel changes every hash in dvc.lock. These hashes were taken from the renderer as it stood before
it was split into a package (issue 13); a deliberate change of the route must update them, and say
so. They cover a moving frame, a station stop, a tunnel and a mid-route place of the default route
(1800 s, seed 0, 256x144) and one place of another seed and size.
"""

from __future__ import annotations

import hashlib

import cv2
import numpy as np
import pytest

from seasonloop.data.synthetic import SEASONS, SyntheticRoute

PINNED = {
    (1800, 0, 256, 144, 0.0, "summer"): "c89ac7f1fbb0feae0c64deb5c92f352c88c40610ce8bf3d0b257772224e096b2",
    (1800, 0, 256, 144, 0.0, "spring"): "1416e6727842209c97a29bedd257dbde0a8dea848826178b8fca0def319b444a",
    (1800, 0, 256, 144, 0.0, "fall"): "b664a2254e3caaebad30f04b561dd9d77828feaa0a0b411a15cc7cb55609ebe0",
    (1800, 0, 256, 144, 0.0, "winter"): "8fe5878021f45a681d9e20a180a1d7dbf9aacc34816cdaa0fd1bca1e3138a8ed",
    (1800, 0, 256, 144, 400.0, "summer"): "f0ceaa3b4b75368c3b5022b15bf922e44c837eeaeef3fc866234d85bbb7bf6af",
    (1800, 0, 256, 144, 400.0, "spring"): "91d93aaae8fd541410753511cc4f0629f4d34b5f2a9cffda4b968b9e8616654e",
    (1800, 0, 256, 144, 400.0, "fall"): "35444e4f862b383de286a994b522812d86687cb3f1968b95b16147b7d4d6eabb",
    (1800, 0, 256, 144, 400.0, "winter"): "8787da22fb44190d3af5e9b8672c833f7357e530fb9a4fc46e760a044b81212b",
    (1800, 0, 256, 144, 1050.0, "summer"): "99e5c906b5886a4dfdad336291756b045e8b275ca1f2ca572ad6b2b94e65f508",
    (1800, 0, 256, 144, 1050.0, "spring"): "d8950b389339b529c2e1a896c9e940122fd688e8c80f076cbf48c517c57da62b",
    (1800, 0, 256, 144, 1050.0, "fall"): "f6c50cfdd92041c545dac0c47808402b92c97088887ca8b53290c514d6c97454",
    (1800, 0, 256, 144, 1050.0, "winter"): "42447d5adae11b2c93ff13c37de7a9863ecf81fa31fb6d2affc7959aaa23a24a",
    (1800, 0, 256, 144, 1300.5, "summer"): "4bcd12b1584dc471cfbc407aea9404960d10056d56d3fa7e6e0c0a8ac07adfe0",
    (1800, 0, 256, 144, 1300.5, "spring"): "2f7049777bc4546af9014cf45858105d9b58b8ca1df4a78249ffe31aefce99f2",
    (1800, 0, 256, 144, 1300.5, "fall"): "8a9e323024b35d64dbc4dea8edde55c2279f65b48149bdbf61df626099c8086f",
    (1800, 0, 256, 144, 1300.5, "winter"): "8be8a3d6839bdd1441bc44be8ea8bf722ae4aeecb8d1117d570b33f4ceab8beb",
    (600, 7, 128, 72, 250.0, "summer"): "bc6fb0a939978761c3b940e99a2ad80a7e28a52735b918d6fb96f2b7863e7a34",
    (600, 7, 128, 72, 250.0, "spring"): "4a26c4e8f8f494ef5d929603145aceccdc36c6280cc3cb24dec7255a854e17b7",
    (600, 7, 128, 72, 250.0, "fall"): "33dbb7548d5733bccadc974fb8122aa551fec49e99fe1916ce1e38905bce20a4",
    (600, 7, 128, 72, 250.0, "winter"): "db432210986d15d4926f0de03bc2d0f0389d08a55042d05838e2816edbf6cabb",
}

LAYOUTS = {
    (1800, 0): (
        ((1046, 1072), (1146, 1172), (1591, 1605)),
        ((385, 438), (547, 589), (689, 749), (804, 852), (1371, 1403)),
    ),
    (600, 7): (((502, 514),), ((30, 56),)),
}


@pytest.fixture(scope="module")
def routes() -> dict:
    return {key: SyntheticRoute(*key) for key in LAYOUTS}


def test_layouts_are_pinned(routes) -> None:
    for key, (tunnels, stops) in LAYOUTS.items():
        layout = routes[key].layout
        assert (layout.tunnels, layout.stops) == (tunnels, stops), key


@pytest.mark.parametrize("case", sorted(PINNED))
def test_frame_pixels_are_pinned(routes, case) -> None:
    seconds, seed, width, height, t, season = case
    image = routes[(seconds, seed)].frame(season, t, width, height)
    digest = hashlib.sha256(np.ascontiguousarray(image).tobytes()).hexdigest()
    assert digest == PINNED[case], (
        f"frame {case} changed (pinned with OpenCV 5.0.0, numpy 2.4; here OpenCV {cv2.__version__}, "
        f"numpy {np.__version__})"
    )


def test_pins_cover_every_season() -> None:
    assert {case[-1] for case in PINNED} == set(SEASONS)
