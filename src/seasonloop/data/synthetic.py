"""Deterministic, procedurally rendered train ride: the default stand-in for the Nordland videos.

A route is generated from ``(seconds, seed)``: a speed profile with station stops and tunnels
(`RouteLayout`), and a world along the track made of scenery zones (forest, meadow, farmland,
lakes, villages, rock cuts, moorland), bridges, houses, single trees, telegraph poles, stations,
hills and a mountain skyline. A frame is a forward-facing cab view at route position ``pos(t)``,
which is the same for every season, so frame ``k`` of every season shows the same place.

Rendering happens in two steps. The geometry of a frame is drawn once into a buffer of
*codes* (material x shade level); each season then only looks the codes up in its own palette
(season colours, light and contrast baked in), adds its own clouds, camera offset and jitter,
slow light changes and sensor noise. This keeps four seasons of a place geometrically identical
while their appearance differs the way Nordland's seasons do, and it is fast.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import cv2
import numpy as np
from tqdm import tqdm

SEASONS: tuple[str, ...] = ("summer", "spring", "fall", "winter")

# --- layout -----------------------------------------------------------------------------------

_EDGE_MARGIN_S = 30  # no tunnel or stop in the first or last 30 s
_EVENT_GAP_S = 40  # seconds between events, room to brake/accelerate and for scenery changes
_TUNNEL_EVERY_S, _TUNNEL_LEN_S = 600.0, (10, 40)
_STOP_EVERY_S, _STOP_LEN_S = 900.0, (20, 60)


@dataclass(frozen=True)
class RouteLayout:
    """Where in video time the train is in a tunnel or stands at a station."""

    seconds: int
    tunnels: tuple[tuple[int, int], ...]  # half-open [start, end) seconds of video time
    stops: tuple[tuple[int, int], ...]  # half-open [start, end) seconds standing still

    def to_json(self) -> dict:
        """Plain-JSON form (lists), inverse of `from_json`."""
        return {
            "seconds": self.seconds,
            "tunnels": [list(span) for span in self.tunnels],
            "stops": [list(span) for span in self.stops],
        }

    @classmethod
    def from_json(cls, data: dict) -> "RouteLayout":
        """Rebuild a layout written by `to_json`; missing keys raise ValueError."""
        for key in ("seconds", "tunnels", "stops"):
            if key not in data:
                raise ValueError(f"route layout JSON lacks key {key!r}")
        return cls(
            seconds=int(data["seconds"]),
            tunnels=tuple((int(a), int(b)) for a, b in data["tunnels"]),
            stops=tuple((int(a), int(b)) for a, b in data["stops"]),
        )

    def _flags(self, spans: tuple[tuple[int, int], ...]) -> np.ndarray:
        flags = np.zeros(self.seconds, dtype=bool)
        for start, end in spans:
            flags[start:end] = True
        return flags

    def in_tunnel(self) -> np.ndarray:
        """Bool (seconds,): True for seconds inside a tunnel."""
        return self._flags(self.tunnels)

    def stopped(self) -> np.ndarray:
        """Bool (seconds,): True for seconds at which the train stands where it stood at t-1."""
        return self._flags(self.stops)


def make_layout(seconds: int, seed: int) -> RouteLayout:
    """Place tunnels (~1 per 600 s, 10-40 s long) and stops (~1 per 900 s, 20-60 s) from the seed.

    Events never overlap, keep `_EVENT_GAP_S` between each other and stay out of the first and last
    30 s; a route of 600 s or more has at least one of each.
    """
    if int(seconds) != seconds or seconds < 1:
        raise ValueError(f"seconds must be a positive integer, got {seconds!r}")
    if int(seed) != seed or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    seconds = int(seconds)
    rng = np.random.default_rng([int(seed), 0x1A7])
    n_tunnels = int(rng.poisson(seconds / _TUNNEL_EVERY_S))
    n_stops = int(rng.poisson(seconds / _STOP_EVERY_S))
    if seconds >= 600:
        n_tunnels, n_stops = max(n_tunnels, 1), max(n_stops, 1)
    events = [("tunnel", int(n)) for n in rng.integers(_TUNNEL_LEN_S[0], _TUNNEL_LEN_S[1] + 1, n_tunnels)]
    events += [("stop", int(n)) for n in rng.integers(_STOP_LEN_S[0], _STOP_LEN_S[1] + 1, n_stops)]
    events = [events[i] for i in rng.permutation(len(events))]
    usable = seconds - 2 * _EDGE_MARGIN_S

    def needed() -> int:
        return sum(n for _, n in events) + _EVENT_GAP_S * max(len(events) - 1, 0)

    # Short routes cannot hold every drawn event: drop from the more numerous kind.
    while events and needed() > usable:
        kinds = [kind for kind, _ in events]
        drop = "tunnel" if kinds.count("tunnel") >= kinds.count("stop") else "stop"
        del events[len(kinds) - 1 - kinds[::-1].index(drop)]
    slack = usable - needed()
    spare = np.floor(rng.dirichlet(np.ones(len(events) + 1)) * slack).astype(int)
    tunnels, stops = [], []
    cursor = _EDGE_MARGIN_S
    for (kind, length), extra in zip(events, spare):
        start = cursor + int(extra)
        (tunnels if kind == "tunnel" else stops).append((start, start + length))
        cursor = start + length + _EVENT_GAP_S
    return RouteLayout(seconds=seconds, tunnels=tuple(tunnels), stops=tuple(stops))


# --- hashing and noise (random access along the route, no stored textures) --------------------

def _mix(*values: int) -> int:
    """Deterministic 64-bit integer hash of a few integers (for per-frame choices)."""
    x = 0x243F6A8885A308D3
    for v in values:
        x = (x ^ (v & 0xFFFFFFFFFFFFFFFF)) * 0x9E3779B97F4A7C15 & 0xFFFFFFFFFFFFFFFF
        x ^= x >> 29
    x = (x * 0xBF58476D1CE4E5B9) & 0xFFFFFFFFFFFFFFFF
    return x ^ (x >> 32)


def _slots(keys: np.ndarray, salt: int | np.ndarray) -> np.ndarray:
    """Cheap multiplicative hash of integer keys (|key| < 2**30) to a slot of a 65536-entry table.

    The tables hold the seeded random numbers, so any place along the route can be generated
    on demand without storing anything per metre.
    """
    return (((keys + np.bitwise_and(salt, 0xFFFFF)) * 0x9E3779B1) >> 12) & 0xFFFF


def _value_noise(x: np.ndarray, salt: int | np.ndarray, table: np.ndarray) -> np.ndarray:
    """Smooth 1-D value noise in [0, 1) from a random table."""
    cell = np.floor(x)
    frac = x - cell
    cell = cell.astype(np.int64)
    a = table[_slots(cell, salt)]
    b = table[_slots(cell + 1, salt)]
    return a + (b - a) * (frac * frac * (3.0 - 2.0 * frac))


def _fbm(x: np.ndarray, salt: int | np.ndarray, table: np.ndarray, octaves: int = 3) -> np.ndarray:
    """Fractal value noise in [0, 1): rugged enough for skylines."""
    total = np.zeros_like(x, dtype=np.float64)
    amplitude, norm = 1.0, 0.0
    for octave in range(octaves):
        total += amplitude * _value_noise(x * (2.0**octave), salt + 977 * octave, table)
        norm += amplitude
        amplitude *= 0.5
    return total / norm


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


# --- materials and season palettes -------------------------------------------------------------

_LEVELS = 32  # shade levels per material; code = material * _LEVELS + level
_MID = 16  # level of unshaded colour

# RGB per season (summer, spring, fall, winter). Winter: snow on ground, trees and roofs, overcast.
_COLOURS: dict[str, tuple[tuple[int, int, int], ...]] = {
    "sky": ((95, 150, 220), (120, 172, 235), (138, 148, 162), (178, 182, 190)),
    "sky_haze": ((175, 200, 228), (195, 215, 238), (165, 170, 178), (192, 194, 198)),
    "mtn_low": ((82, 102, 104), (96, 114, 112), (112, 102, 88), (186, 190, 198)),
    "mtn_rock": ((110, 120, 138), (120, 128, 146), (112, 116, 128), (176, 181, 192)),
    "mtn_patch": ((118, 128, 146), (226, 231, 240), (120, 124, 136), (214, 218, 226)),
    "mtn_top": ((160, 168, 184), (232, 236, 244), (196, 200, 210), (222, 226, 232)),
    "hill_forest": ((46, 80, 50), (76, 108, 64), (116, 92, 52), (150, 156, 162)),
    "hill_bare": ((104, 112, 92), (118, 116, 96), (122, 98, 72), (210, 214, 222)),
    "hill_patch": ((104, 112, 92), (226, 230, 236), (122, 98, 72), (222, 226, 232)),
    "spruce": ((24, 54, 30), (36, 68, 36), (28, 50, 28), (66, 78, 72)),
    "spruce_lit": ((40, 80, 42), (58, 98, 50), (42, 70, 38), (222, 226, 232)),
    "birch_a": ((58, 112, 38), (128, 168, 66), (206, 168, 48), (112, 108, 104)),
    "birch_b": ((70, 124, 44), (146, 180, 78), (210, 128, 40), (126, 120, 116)),
    "birch_c": ((52, 100, 36), (116, 156, 60), (160, 70, 40), (100, 96, 94)),
    "understorey": ((20, 30, 20), (30, 38, 26), (32, 28, 22), (150, 154, 160)),
    "grass": ((78, 124, 52), (122, 150, 62), (136, 120, 62), (228, 232, 238)),
    "verge": ((92, 116, 60), (128, 134, 78), (128, 112, 70), (214, 218, 224)),
    "forest_floor": ((48, 78, 34), (90, 98, 54), (102, 80, 44), (218, 222, 228)),
    "field_a": ((96, 150, 50), (126, 104, 74), (192, 162, 82), (234, 236, 240)),
    "field_b": ((80, 134, 44), (140, 160, 70), (160, 126, 70), (222, 226, 232)),
    "moor": ((100, 114, 60), (124, 114, 74), (132, 90, 56), (228, 231, 236)),
    "water": ((58, 88, 128), (78, 116, 158), (72, 82, 94), (204, 209, 217)),
    "ballast": ((112, 106, 98), (120, 114, 104), (100, 95, 88), (196, 198, 203)),
    "sleeper": ((76, 64, 54), (80, 70, 60), (70, 60, 52), (160, 162, 168)),
    "rail": ((172, 172, 176), (176, 176, 180), (150, 150, 155), (96, 96, 102)),
    "rail_dark": ((60, 54, 50), (64, 58, 54), (56, 50, 46), (84, 84, 90)),
    "rock": ((104, 104, 100), (114, 112, 106), (94, 92, 88), (148, 151, 158)),
    "rock_top": ((80, 110, 60), (110, 124, 70), (122, 96, 56), (228, 231, 236)),
    "house_red": ((152, 40, 34), (158, 44, 38), (136, 38, 32), (138, 52, 46)),
    "house_white": ((226, 226, 220), (232, 232, 226), (206, 206, 200), (212, 212, 212)),
    "house_yellow": ((216, 180, 90), (222, 186, 96), (196, 162, 84), (198, 174, 112)),
    "roof_dark": ((52, 52, 58), (56, 56, 62), (48, 48, 54), (228, 230, 236)),
    "roof_red": ((122, 50, 40), (128, 54, 44), (110, 46, 38), (228, 230, 236)),
    "window": ((40, 46, 58), (44, 50, 62), (36, 40, 50), (62, 64, 72)),
    "pole": ((86, 66, 46), (90, 70, 50), (74, 58, 42), (76, 64, 52)),
    "wire": ((44, 44, 44), (48, 48, 48), (42, 42, 42), (92, 92, 96)),
    "steel": ((92, 102, 96), (98, 108, 102), (86, 94, 90), (124, 128, 134)),
    "platform": ((150, 148, 142), (156, 154, 148), (136, 134, 128), (218, 220, 225)),
    "platform_edge": ((230, 210, 60), (236, 216, 66), (210, 190, 56), (196, 196, 186)),
    "tunnel": ((40, 36, 32), (40, 36, 32), (40, 36, 32), (40, 36, 32)),
    "lamp": ((170, 140, 80), (170, 140, 80), (170, 140, 80), (170, 140, 80)),
    "daylight": ((240, 242, 238), (244, 246, 244), (226, 228, 228), (236, 237, 240)),
    "trunk": ((196, 192, 182), (200, 196, 186), (186, 180, 170), (150, 146, 140)),
    "sign": ((232, 232, 232), (236, 236, 236), (214, 214, 214), (226, 226, 226)),
}
_MATERIAL_NAMES = tuple(_COLOURS)
_MAT = {name: index for index, name in enumerate(_MATERIAL_NAMES)}

# Global light per season: channel gains (RGB), contrast around a pivot, how much of the
# directional shading survives (flat overcast light in fall and winter).
_GRADE = {
    "summer": {"gain": (1.00, 1.00, 1.00), "contrast": 1.00, "pivot": 120.0, "shading": 1.00},
    "spring": {"gain": (1.05, 1.05, 1.07), "contrast": 1.00, "pivot": 120.0, "shading": 0.90},
    "fall": {"gain": (0.95, 0.90, 0.84), "contrast": 0.95, "pivot": 120.0, "shading": 0.70},
    "winter": {"gain": (0.95, 0.97, 1.02), "contrast": 0.5, "pivot": 180.0, "shading": 0.40},
}
# Clouds per season: sky fraction covered, colour (RGB), opacity.
_CLOUDS = {
    "summer": (0.35, (246, 246, 248), 0.85),
    "spring": (0.18, (250, 250, 252), 0.80),
    "fall": (0.70, (148, 150, 156), 0.75),
    "winter": (0.90, (204, 205, 209), 0.35),
}


def _code(material: str, level: int | np.ndarray) -> int | np.ndarray:
    return _MAT[material] * _LEVELS + level


def _palette(season: str) -> np.ndarray:
    """(materials * levels, 3) uint8 BGR lookup table with season colour and light baked in."""
    s_index = SEASONS.index(season)
    grade = _GRADE[season]
    base = np.array([_COLOURS[name][s_index] for name in _MATERIAL_NAMES], dtype=np.float64)
    shade = 1.0 + (np.arange(_LEVELS) / (_LEVELS - 1) - 0.5) * grade["shading"]
    colours = np.clip(base[:, None, :] * shade[None, :, None], 0, 255)
    colours = colours * np.array(grade["gain"])
    graded = grade["pivot"] + (colours - grade["pivot"]) * grade["contrast"]
    # Tunnels are lit by lamps and headlights, not by the season's sky: no contrast change there.
    lamp_lit = np.isin(np.arange(len(_MATERIAL_NAMES)), [_MAT[name] for name in ("tunnel", "lamp", "daylight")])
    colours = np.where(lamp_lit[:, None, None], colours, graded)
    rgb = np.clip(np.rint(colours), 0, 255).astype(np.uint8).reshape(-1, 3)
    return np.ascontiguousarray(rgb[:, ::-1])


# --- world --------------------------------------------------------------------------------------

_CAM_HEIGHT = 3.2  # m above rail
_FOCAL = 0.6  # focal length as a fraction of image width (about 80 degrees horizontal view)
_HORIZON = 0.42  # horizon row as a fraction of image height
_Z_NEAR = 1.0  # m, near clipping plane
_GAUGE_HALF = 0.7175  # m, half the standard gauge
_POLE_SPACING = 50.0  # m between telegraph poles
_OBJECT_RANGE = 600.0  # m ahead within which discrete objects are drawn
_PORTAL_APPROACH = 450.0  # m of rock cut in front of a tunnel portal
_PORTAL_EXIT = 120.0  # m of rock cut behind a tunnel exit
_STATION_BEFORE, _STATION_AFTER = 350.0, 250.0  # m of station surroundings around a stop

_FOREST, _MEADOW, _FIELD, _WATER, _VILLAGE, _ROCKCUT, _MOOR = range(7)
_N_ZONES = 7
# Ground per zone: material near the track (3.2 m to the edge), edge distance, material beyond.
_GROUND = {
    _FOREST: ("verge", 5.0, "forest_floor"),
    _MEADOW: ("grass", 5.0, "grass"),
    _FIELD: ("grass", 6.0, "field_a"),
    _WATER: ("rock", 5.0, "water"),
    _VILLAGE: ("grass", 5.0, "grass"),
    _ROCKCUT: ("ballast", 4.4, "rock"),
    _MOOR: ("moor", 4.5, "moor"),
}
# Lateral bands of the ground (m from the track centre): ballast with sleepers, ballast, shoulder
# (bridge deck edge), shoulder, then bands whose lower bounds are `_BAND_LOWER`; the last two
# bands are alternate stripes of a ploughed field.
_GROUND_BANDS = np.array([1.25, 1.6, 1.9, 3.2, 4.4, 4.5, 5.0, 6.0])
_BAND_LOWER = np.array([3.2, 4.4, 4.5, 5.0, 6.0, 6.0])
_N_BANDS = len(_GROUND_BANDS) + 2
_GROUND_INNER = np.array([_MAT[_GROUND[k][0]] for k in range(_N_ZONES)])
_GROUND_EDGE = np.array([_GROUND[k][1] for k in range(_N_ZONES)])
_GROUND_OUTER = np.array([_MAT[_GROUND[k][2]] for k in range(_N_ZONES)])
# Regions give long stretches their character: zone weights and the share of spruce vs birch.
_REGIONS = (
    # coast
    ({_WATER: 0.32, _FIELD: 0.2, _MEADOW: 0.16, _FOREST: 0.14, _VILLAGE: 0.12, _ROCKCUT: 0.06}, 0.4),
    # forested valley
    ({_FOREST: 0.48, _MEADOW: 0.2, _FIELD: 0.1, _WATER: 0.1, _ROCKCUT: 0.07, _VILLAGE: 0.05}, 0.75),
    # farmland
    ({_FIELD: 0.42, _MEADOW: 0.2, _VILLAGE: 0.16, _FOREST: 0.16, _WATER: 0.06}, 0.5),
    # mountain plateau (Saltfjellet-like): moor, birch scrub, lakes
    ({_MOOR: 0.45, _ROCKCUT: 0.12, _FOREST: 0.15, _WATER: 0.18, _MEADOW: 0.1}, 0.1),
)


@dataclass(frozen=True)
class _TreeLayer:
    """A row of trees parallel to the track at a fixed lateral distance, on both sides."""

    lateral: float  # m from the track centre
    cell: float  # m of route per tree slot
    reach: int  # neighbouring slots searched on each side for crowns covering a column
    height: tuple[float, float]  # m
    occupancy: tuple[float, ...]  # chance a slot holds a tree, per zone type
    understorey: bool  # dark trunk zone at the bottom (near rows only)
    detail: bool  # branch tiers and leaf texture (visible only on nearer rows)
    salt: int


_TREE_LAYERS = (
    _TreeLayer(170.0, 10.0, 1, (12.0, 22.0), (0.95, 0.95, 0.9, 0.0, 0.9, 0.9, 0.2), False, False, 11),
    _TreeLayer(65.0, 8.0, 2, (10.0, 20.0), (0.9, 0.9, 0.5, 0.0, 0.7, 0.8, 0.12), False, True, 12),
    _TreeLayer(22.0, 7.0, 3, (10.0, 20.0), (0.9, 0.85, 0.0, 0.0, 0.3, 0.6, 0.08), True, True, 13),
    _TreeLayer(7.0, 5.0, 3, (11.0, 22.0), (0.97, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0), True, True, 14),
)
_ZONE_TREE_SCALE = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.3])  # moorland: low birch scrub
_ROCK_LATERAL = 4.5
_HILLS = ((1300.0, 150.0, 650.0, 2500.0, 21), (420.0, 60.0, 260.0, 900.0, 22))  # X, base, relief, scale, salt
_MOUNTAIN_DISTANCE = 10000.0  # m, the skyline range straight ahead
# Skyline codes by (layer 0: range ahead, 4: hills) + altitude band (low, bare, snow patch, top).
_SKYLINE_CODES = np.array(
    [_MAT[name] * _LEVELS for name in ("mtn_low", "mtn_rock", "mtn_patch", "mtn_top")]
    + [_MAT[name] * _LEVELS for name in ("hill_forest", "hill_bare", "hill_patch", "hill_patch")],
    dtype=np.int32,
)


class _Zones:
    """Scenery zone per route position on one side: sorted segment starts and their attributes."""

    def __init__(self, starts: np.ndarray, types: np.ndarray, heights: np.ndarray, spruce: np.ndarray):
        self.starts, self.types, self.heights, self.spruce = starts, types, heights, spruce

    def index(self, s: np.ndarray) -> np.ndarray:
        return np.searchsorted(self.starts, s, side="right") - 1

    def paint(self, a: float, b: float, zone_type: int) -> None:
        """Force [a, b) to `zone_type`, keeping the attributes of the segments underneath."""
        i_a, i_b = int(self.index(np.array([a]))[0]), int(self.index(np.array([b]))[0])
        before, after = self.starts < a, self.starts > b
        def splice(values: np.ndarray, at_a, at_b) -> np.ndarray:
            return np.concatenate([values[before], [at_a, at_b], values[after]])

        self.types = splice(self.types, zone_type, self.types[i_b])
        self.heights = splice(self.heights, self.heights[i_a], self.heights[i_b])
        self.spruce = splice(self.spruce, self.spruce[i_a], self.spruce[i_b])
        self.starts = splice(self.starts, a, b)

    def segments(self) -> list[tuple[float, float, int]]:
        ends = np.append(self.starts[1:], np.inf)
        return [(float(a), float(b), int(k)) for a, b, k in zip(self.starts, ends, self.types)]


class _View:
    """Per-image-size camera geometry that does not change from frame to frame."""

    def __init__(self, width: int, height: int):
        self.width, self.height = width, height
        self.focal = _FOCAL * width
        self.cx = width / 2.0
        self.horizon = _HORIZON * height
        offset = np.arange(width) + 0.5 - self.cx
        self.col_offset = offset
        self.col_dist = np.maximum(np.abs(offset), 0.5)
        self.col_index = np.arange(width)
        # The mountain range ahead between two morph keys, cached: (key, heights at key, at key+1).
        self.ranges: tuple[int | None, np.ndarray | None, np.ndarray | None] = (None, None, None)
        self.left = offset < 0
        self.first_ground_row = int(math.floor(self.horizon)) + 1
        self.row_centre = (np.arange(height) + 0.5).astype(np.float32)
        ground_y = self.row_centre[self.first_ground_row :].astype(np.float64)
        self.ground_z = self.focal * _CAM_HEIGHT / (ground_y - self.horizon)
        self.ground_x = offset[None, :] * self.ground_z[:, None] / self.focal
        self.ground_absx = np.abs(self.ground_x)
        # Texture detail fades out with distance (it would only alias further away).
        self.grain_amp = np.clip(1.0 - self.ground_z / 60.0, 0.0, 1.0).astype(np.float32)[:, None]
        self.ground_xi_fine = ((self.ground_x * 3.0 + 3000).astype(np.int32) & 255)
        self.ground_xi_coarse = ((self.ground_x / 6.0 + 1000).astype(np.int32) & 255)
        band = np.searchsorted(_GROUND_BANDS, self.ground_absx, side="right")
        stripe = (self.ground_absx / 2.5).astype(np.int64) & 1
        band = np.where((band == _N_BANDS - 2) & (stripe == 1), _N_BANDS - 1, band)
        rows = np.arange(len(self.ground_z))[:, None]
        self.ground_band_index = ((rows * 2 + (~self.left)[None, :]) * _N_BANDS + band).astype(np.int64)
        sky_rows = self.first_ground_row
        rel = (self.row_centre[:sky_rows] / max(self.horizon, 1.0))[:, None]
        sky_level = np.rint(11 + 9 * rel).astype(np.int64)
        sky = np.where(rel > 0.85, _code("sky_haze", np.rint(14 + 4 * rel).astype(np.int64)), _code("sky", sky_level))
        self.sky = np.broadcast_to(sky, (sky_rows, width)).astype(np.uint16)

    def project(self, x: float, y: float, z: float) -> tuple[float, float]:
        """World (lateral x, height y above rail, distance z ahead) to pixel (u, v)."""
        return self.cx + self.focal * x / z, self.horizon + self.focal * (_CAM_HEIGHT - y) / z


def _clip_near(points: list[tuple[float, float, float]]) -> list[tuple[float, float, float]]:
    """Clip a convex polygon to z >= _Z_NEAR (Sutherland-Hodgman, one plane)."""
    out = []
    n = len(points)
    for i in range(n):
        a, b = points[i], points[(i + 1) % n]
        a_in, b_in = a[2] >= _Z_NEAR, b[2] >= _Z_NEAR
        if a_in:
            out.append(a)
        if a_in != b_in:
            w = (_Z_NEAR - a[2]) / (b[2] - a[2])
            out.append((a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), _Z_NEAR))
    return out


_SHIFT = 4  # sub-pixel bits for cv2 drawing
_SCALE = float(1 << _SHIFT)
_LIMIT = 1.0e5  # keep projected coordinates inside int32 after the shift


def _pixel(view: _View, x: float, y: float, z: float) -> tuple[int, int]:
    """Project to fixed-point pixel coordinates for cv2 drawing with `_SHIFT` fractional bits."""
    u, v = view.project(x, y, z)
    return (int(min(max(u * _SCALE, -_LIMIT), _LIMIT)), int(min(max(v * _SCALE, -_LIMIT), _LIMIT)))


def _to_pixels(view: _View, points: list[tuple[float, float, float]]) -> np.ndarray:
    return np.array([_pixel(view, *point) for point in points], dtype=np.int32)


def _fill(codes: np.ndarray, view: _View, points: list[tuple[float, float, float]], code: int) -> None:
    """Fill a convex world polygon (clipped at the near plane) with one code."""
    clipped = _clip_near(points)
    if len(clipped) >= 3:
        cv2.fillConvexPoly(codes, _to_pixels(view, clipped), int(code), cv2.LINE_8, _SHIFT)


def _polyline(codes: np.ndarray, view: _View, points: list[tuple[float, float, float]], code: int) -> None:
    """One-pixel line through world points ordered by distance (nearest first), clipped at the near plane."""
    visible = [point for point in points if point[2] >= _Z_NEAR]
    if not visible:
        return
    first = points.index(visible[0])
    if first > 0:
        a, b = visible[0], points[first - 1]
        w = (_Z_NEAR - a[2]) / (b[2] - a[2])
        visible.insert(0, (a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), _Z_NEAR))
    if len(visible) >= 2:
        cv2.polylines(codes, [_to_pixels(view, visible)], False, int(code), 1, cv2.LINE_8, _SHIFT)


def _segment(codes: np.ndarray, view: _View, a: tuple, b: tuple, code: int, thickness_m: float) -> None:
    """Draw a world line segment whose pixel width follows its distance."""
    if a[2] < _Z_NEAR and b[2] < _Z_NEAR:
        return
    if a[2] < _Z_NEAR or b[2] < _Z_NEAR:
        if a[2] < _Z_NEAR:
            a, b = b, a
        w = (_Z_NEAR - a[2]) / (b[2] - a[2])
        b = (a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), _Z_NEAR)
    thickness = int(min(max(round(view.focal * thickness_m / min(a[2], b[2])), 1), 64))
    cv2.line(codes, _pixel(view, *a), _pixel(view, *b), int(code), thickness, cv2.LINE_8, _SHIFT)


class SyntheticRoute:
    """A synthetic Nordland-style route: layout, speed profile and world, all from (seconds, seed).

    `frame(season, t, width, height)` renders the cab view at video time t (seconds).
    Memory is independent of image count: only small per-second/per-segment arrays are kept.
    """

    _TIME_STEP = 0.25  # s, resolution of the integrated position

    def __init__(self, seconds: int, seed: int):
        self.layout = make_layout(seconds, seed)
        self.seconds = self.layout.seconds
        self.seed = int(seed)
        self._build_motion()
        rng = np.random.default_rng([self.seed, 0x3D])
        # Seeded texture tables (256 x 256, looked up by world coordinates): fine grain in -3..3
        # and smooth unit-variance patches.
        grain = np.clip(np.rint(rng.normal(0.0, 1.4, (256, 256))), -3, 3)
        # Smooth noise that tiles seamlessly: blur a 3x3 tiling and keep the middle tile.
        tiled = np.tile(rng.normal(0.0, 1.0, (256, 256)).astype(np.float32), (3, 3))
        patches = cv2.GaussianBlur(tiled, (0, 0), 6)[256:512, 256:512]
        patches = (patches - patches.mean()) / patches.std()
        self._patches_flat = patches.astype(np.float32).ravel()
        self._grain_flat = grain.astype(np.float32).ravel()
        self._grain_int_flat = grain.astype(np.int32).ravel()
        self._coarse_flat = (_MID + np.rint(1.5 * patches)).astype(np.int32).ravel()
        self._table = rng.random((8, 1 << 16))  # random attributes of trees, looked up by `_slots`
        self._build_zones(rng)
        self._build_objects(rng)
        self._views: dict[tuple[int, int], _View] = {}
        self._looks: dict[tuple[int, int, int], _SeasonLook] = {}
        self._cached_codes: tuple[tuple[float, int, int], np.ndarray] | None = None

    # -- motion -----------------------------------------------------------------------------------

    def _build_motion(self) -> None:
        """Integrate a smooth speed profile that is exactly zero during stops."""
        rng = np.random.default_rng([self.seed, 0x5EED])
        self._t_grid = np.arange(0.0, self.seconds + self._TIME_STEP / 2, self._TIME_STEP)
        t = self._t_grid
        speed = np.full_like(t, 21.0)  # m/s, about 75 km/h
        for amplitude, period in ((5.0, 700.0), (3.0, 260.0), (1.5, 90.0)):
            speed += amplitude * np.sin(2 * np.pi * t / (period * rng.uniform(0.8, 1.25)) + rng.uniform(0, 2 * np.pi))
        ramp = 16.0  # s to brake or accelerate
        for start, end in self.layout.stops:
            # Standing on [start-1, end-1] makes pos(t) == pos(t-1) exactly for t in [start, end).
            arrive, leave = start - 1.0, end - 1.0
            factor = np.ones_like(t)
            factor = np.where(t < arrive, _smoothstep((arrive - t) / ramp), factor)
            factor = np.where(t > leave, _smoothstep((t - leave) / ramp), factor)
            factor[(t >= arrive) & (t <= leave)] = 0.0
            speed *= factor
        steps = (speed[1:] + speed[:-1]) * (self._TIME_STEP / 2)
        self._pos_grid = np.concatenate([[0.0], np.cumsum(steps)])
        self._speed_grid = speed
        self.length = float(self._pos_grid[-1])

    def position(self, t: float | np.ndarray) -> float | np.ndarray:
        """Train position along the route (m) at video time t (s); the same for every season."""
        return np.interp(t, self._t_grid, self._pos_grid)

    # -- world ------------------------------------------------------------------------------------

    def _build_zones(self, rng: np.random.Generator) -> None:
        """Scenery zones per side, overridden around stations, tunnels and bridges."""
        end = self.length + 4000.0
        starts, left, right, heights_l, heights_r, spruce = [], [], [], [], [], []
        bridges = []
        s = -1000.0
        region_end = -np.inf
        while s < end:
            if s >= region_end:
                region_types, spruce_share = _REGIONS[int(rng.integers(len(_REGIONS)))]
                kinds = np.array(list(region_types))
                weights = np.array([region_types[k] for k in kinds])
                weights = weights / weights.sum()
                region_end = s + rng.uniform(3000.0, 12000.0)
            length = rng.uniform(120.0, 600.0)
            if rng.random() < 0.06:  # a river with a bridge
                span = rng.uniform(40.0, 160.0)
                bridges.append((s + 30.0, s + 30.0 + span))
                length = span + 60.0
                kind_l = kind_r = _WATER
            else:
                kind_l = int(rng.choice(kinds, p=weights))
                kind_r = kind_l if rng.random() < 0.45 else int(rng.choice(kinds, p=weights))
            starts.append(s)
            left.append(kind_l)
            right.append(kind_r)
            heights_l.append(rng.uniform(0.75, 1.25))
            heights_r.append(rng.uniform(0.75, 1.25))
            spruce.append(float(np.clip(spruce_share + rng.normal(0.0, 0.15), 0.0, 1.0)))
            s += length
        starts_a = np.array(starts)
        self._zones = (
            _Zones(starts_a, np.array(left, dtype=np.int64), np.array(heights_l), np.array(spruce)),
            _Zones(starts_a.copy(), np.array(right, dtype=np.int64), np.array(heights_r), np.array(spruce)),
        )
        blocked = []
        self._stations = []
        for start, _ in self.layout.stops:
            at = float(self.position(start))
            side = 1 if rng.random() < 0.5 else -1
            a, b = at - _STATION_BEFORE, at + _STATION_AFTER
            self._zones[0 if side < 0 else 1].paint(a, b, _VILLAGE)
            self._zones[1 if side < 0 else 0].paint(a, b, _MEADOW)
            blocked.append((a, b))
            self._stations.append((at, side))
        tunnels = []
        for start, stop in self.layout.tunnels:
            a, b = float(self.position(start)), float(self.position(stop))
            for zones in self._zones:
                zones.paint(a - _PORTAL_APPROACH, b + _PORTAL_EXIT, _ROCKCUT)
            blocked.append((a - _PORTAL_APPROACH, b + _PORTAL_EXIT))
            tunnels.append((a, b))
        self._tunnel_a = np.array([a for a, _ in tunnels])
        self._tunnel_b = np.array([b for _, b in tunnels])
        self._tunnel_shape = rng.uniform(0.0, 1.0, (len(tunnels), 4))
        kept = [(a, b) for a, b in bridges if not any(a < y and x < b for x, y in blocked)]
        self._bridge_a = np.array([a for a, _ in kept])
        self._bridge_b = np.array([b for _, b in kept])

    def _build_objects(self, rng: np.random.Generator) -> None:
        """Houses and single trees per zone, after the zone overrides."""
        houses: list[tuple] = []  # s, side, lateral, length, depth, wall, roof, wall mat, roof mat
        trees: list[tuple] = []  # s, side, lateral, height, spruce?
        colours = ("house_red", "house_white", "house_yellow")
        station_sides = {side: [at for at, station_side in self._stations if station_side == side] for side in (-1, 1)}
        for at, side in self._stations:
            wall = colours[int(rng.integers(3))]
            houses.append((at + 8.0, side, 9.0, 20.0, 9.0, 5.5, 3.0, wall, "roof_dark"))
        for side, zones in zip((-1, 1), self._zones):
            for a, b, kind in zones.segments():
                b = min(b, self.length + 1000.0)
                if b <= a:
                    continue
                if kind == _VILLAGE:
                    s = a + rng.uniform(0.0, 30.0)
                    while s < b - 15.0:
                        if any(at - 30.0 < s < at + 40.0 for at in station_sides[side]):
                            s += 10.0  # leave room for the station building
                            continue
                        colour = colours[int(rng.choice(3, p=(0.35, 0.4, 0.25)))]
                        roof = "roof_dark" if rng.random() < 0.6 else "roof_red"
                        houses.append((s, side, rng.uniform(9.0, 30.0), rng.uniform(8.0, 14.0), rng.uniform(6.0, 10.0),
                                       rng.uniform(3.0, 5.5), rng.uniform(2.0, 3.5), colour, roof))
                        if rng.random() < 0.5:
                            lateral, height = rng.uniform(6.0, 14.0), rng.uniform(6.0, 14.0)
                            trees.append((s + rng.uniform(5.0, 20.0), side, lateral, height, rng.random() < 0.4))
                        s += rng.uniform(25.0, 60.0)
                elif kind == _FIELD and b - a > 150.0 and rng.random() < 0.6:
                    s = rng.uniform(a, b - 60.0)
                    lateral = rng.uniform(30.0, 90.0)
                    houses.append((s, side, lateral, 12.0, 9.0, 5.0, 3.0, "house_white", "roof_dark"))
                    houses.append((s + 25.0, side, lateral + 5.0, 24.0, 12.0, 6.0, 4.5, "house_red", "roof_dark"))
                if kind in (_FIELD, _MEADOW, _MOOR, _VILLAGE):
                    count = int(rng.poisson({_FIELD: 2.0, _MEADOW: 3.0, _MOOR: 8.0, _VILLAGE: 2.0}[kind]))
                    small = kind == _MOOR
                    for _ in range(count):
                        height = rng.uniform(2.0, 5.0) if small else rng.uniform(7.0, 16.0)
                        spruce = (not small) and rng.random() < 0.5
                        trees.append((rng.uniform(a, b), side, rng.uniform(6.0, 60.0), height, spruce))
        houses.sort(key=lambda h: h[0])
        trees.sort(key=lambda tr: tr[0])
        self._houses = houses
        self._house_s = np.array([h[0] for h in houses])
        self._trees = trees
        self._tree_s = np.array([tr[0] for tr in trees])

    # -- frames -----------------------------------------------------------------------------------

    def _view(self, width: int, height: int) -> _View:
        key = (width, height)
        if key not in self._views:
            self._views[key] = _View(width, height)
        return self._views[key]

    def _look(self, season: str, width: int, height: int) -> "_SeasonLook":
        key = (SEASONS.index(season), width, height)
        if key not in self._looks:
            self._looks[key] = _SeasonLook(self.seed, season, self._view(width, height))
        return self._looks[key]

    def frame(self, season: str, t: float, width: int, height: int) -> np.ndarray:
        """Cab view of `season` at video time t: (height, width, 3) uint8 BGR."""
        if season not in SEASONS:
            raise ValueError(f"unknown season {season!r}; expected one of {SEASONS}")
        if not 0.0 <= t <= self.seconds:
            raise ValueError(f"time t={t!r} is outside the route [0, {self.seconds}] s")
        if int(width) != width or int(height) != height or width < 16 or height < 16:
            raise ValueError(f"frame size must be integers >= 16, got width={width!r} height={height!r}")
        width, height = int(width), int(height)
        key = (float(t), width, height)
        if self._cached_codes is None or self._cached_codes[0] != key:
            # Geometry is shared by all seasons at the same time: render it once.
            self._cached_codes = (key, self._render_codes(float(t), self._view(width, height)))
        # The cab shakes with the track: hardly at all while the train stands still.
        shake = 0.1 + 0.9 * min(float(np.interp(t, self._t_grid, self._speed_grid)) / 25.0, 1.0)
        return self._look(season, width, height).colourise(self._cached_codes[1], float(t), shake)

    def _render_codes(self, t: float, view: _View) -> np.ndarray:
        p = float(self.position(t))
        i = int(np.searchsorted(self._tunnel_a, p, side="right")) - 1
        if i >= 0 and p < self._tunnel_b[i]:
            return self._tunnel_codes(view, float(self._tunnel_b[i] - p), p)
        portal = float(self._tunnel_a[i + 1] - p) if i + 1 < len(self._tunnel_a) else np.inf
        portal = portal if portal < _PORTAL_APPROACH else np.inf
        codes = np.empty((view.height, view.width), dtype=np.uint16)
        codes[: view.first_ground_row] = view.sky
        self._draw_ground(codes, view, p)
        self._draw_skyline(codes, view, p)
        self._draw_rails(codes, view, min(portal, 3000.0))
        objects = self._visible_objects(codes, view, p, min(portal, _OBJECT_RANGE))
        drawn = 0
        layers: list[tuple[float, Callable[[], None]]] = []
        for layer in _TREE_LAYERS:
            layers.append((layer.lateral, lambda layer=layer: self._draw_trees(codes, view, p, layer)))
        if np.isfinite(portal):
            layers.append((_ROCK_LATERAL + 0.01, lambda: self._draw_portal(codes, view, portal, i + 1)))
        layers.append((_ROCK_LATERAL, lambda: self._draw_rock(codes, view, p, min(portal, 2000.0))))
        # Painter's order by lateral distance: a side object is hidden only by rows of trees
        # nearer to the track than itself.
        for lateral, draw_layer in layers:
            while drawn < len(objects) and objects[drawn][0] > lateral:
                objects[drawn][2]()
                drawn += 1
            draw_layer()
        for _, _, draw_object in objects[drawn:]:
            draw_object()
        return codes

    # -- layers -------------------------------------------------------------------------------------

    def _skyline_layers(self, view: _View, p: float) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Per column (distance, skyline height above rail, position along the ridge) of the
        mountain range ahead (index 0) and of the far and near hill ridges beside the track (1, 2)."""
        distance = np.full(view.width, _MOUNTAIN_DISTANCE)
        # The range ahead morphs slowly as the train advances (every 6 km it has become a new
        # range): the farthest layer changes slowest.
        a = view.col_offset / view.focal * _MOUNTAIN_DISTANCE / 1800.0
        morph = p / 6000.0
        m0 = math.floor(morph)
        w = float(_smoothstep(np.array(morph - m0)))
        if view.ranges[0] != m0:
            view.ranges = (m0, _fbm(a + 37.0 * m0, 301, self._table[7], 4),
                           _fbm(a + 37.0 * (m0 + 1.0), 301, self._table[7], 4))
        _, h0, h1 = view.ranges
        heights = 250.0 + 1150.0 * np.clip((h0 + (h1 - h0) * w) * 1.6 - 0.45, 0.0, 1.0)
        layers = [(distance, heights, a * 1800.0)]
        for lateral, base, relief, scale, salt in _HILLS:
            # Ridges parallel to the track: nearer ridges sweep outward faster (parallax).
            z = view.focal * lateral / view.col_dist
            s = p + z
            salted = salt + np.where(view.left, 0, 5000)
            heights = base + relief * np.clip(1.5 * _fbm(s / scale, salted, self._table[7]) - 0.25, 0.0, 1.0)
            if lateral < 1000.0 and len(self._tunnel_a):
                # The mountain a tunnel goes through rises over the nearer ridge.
                j = np.clip(np.searchsorted(self._tunnel_a, s), 0, len(self._tunnel_a) - 1)
                centre = (self._tunnel_a[j] + self._tunnel_b[j]) / 2.0
                half = (self._tunnel_b[j] - self._tunnel_a[j]) / 2.0 + 700.0
                heights = heights + 320.0 * np.cos(np.clip((s - centre) / half, -1.0, 1.0) * np.pi / 2) ** 2
            layers.append((z, heights, s))
        return layers

    def _draw_skyline(self, codes: np.ndarray, view: _View, p: float) -> None:
        """Mountains and hills in one pass over the rows above the horizon: each pixel shows the
        nearest layer covering it, banded by altitude into forest, bare rock, snow patches and
        snow-capped tops. (Below the horizon these layers are farther than the ground there.)"""
        layers = self._skyline_layers(view, p)
        width = view.width
        tops = np.empty((3, width), dtype=np.float32)
        per_column = np.empty((5, 3, width), dtype=np.float32)  # offset, scale, level, texture col, grain col
        for index, (z, heights, along) in enumerate(layers):
            tops[index] = view.horizon + view.focal * (_CAM_HEIGHT - heights) / z
            # altitude(y) = offset - y * scale
            per_column[0, index] = view.horizon * z / view.focal
            per_column[1, index] = z / view.focal
            # Slopes facing the sun (left) are lighter; farther layers are hazier.
            haze = (1, 2, 0)[index]
            per_column[2, index] = _MID + haze - np.rint(3.0 * np.clip(np.gradient(tops[index]), -1.5, 1.5))
            per_column[3, index] = (along / 90.0).astype(np.int64) & 255
            per_column[4, index] = (along / 12.0).astype(np.int64) & 255
        r0 = max(int(math.floor(tops.min())), 0)
        r1 = view.first_ground_row
        if r1 <= r0:
            return
        y = view.row_centre[r0:r1, None]
        near, far, ahead = y >= tops[2], y >= tops[1], y >= tops[0]
        # Flat index of the covering layer's per-column values.
        index = np.where(near, 2 * width, np.where(far, width, 0)) + view.col_index
        offset, scale, level, tex_col, grain_col = (np.take(values, index) for values in per_column)
        altitude = offset - y * scale
        texture = _texture(self._patches_flat, altitude * np.float32(1.0 / 40.0), tex_col)
        band = np.where(altitude > 330.0 + 70.0 * texture, 1, 0)
        band = np.where((altitude > 560.0) & (texture > 0.0), 2, band)
        band = np.where(altitude > 950.0 + 80.0 * texture, 3, band)
        # Fine grain: stands of forest and scree on the slopes.
        grain = _texture(self._grain_flat, altitude * np.float32(1.0 / 6.0), grain_col)
        hills = index >= width
        code = np.take(_SKYLINE_CODES, band + 4 * hills) + (level + texture + grain).astype(np.int32)
        np.copyto(codes[r0:r1], code, where=ahead | far | near, casting="unsafe")

    def _draw_ground(self, codes: np.ndarray, view: _View, p: float) -> None:
        """Ground plane: ballast and sleepers, shoulder, and each side's zone ground.

        Each pixel belongs to a fixed lateral band (`_GROUND_BANDS`); per frame only a small
        (row, side, band) table of materials is built and looked up.
        """
        s = p + view.ground_z
        table = np.empty((len(s), 2, _N_BANDS), dtype=np.int32)
        sleeper_rows = (view.ground_z < 12.0) & (np.mod(s, 0.6) < 0.22)
        table[:, :, 0] = np.where(sleeper_rows, _MAT["sleeper"], _MAT["ballast"])[:, None]
        table[:, :, 1] = _MAT["ballast"]
        table[:, :, 2:4] = _MAT["verge"]
        for side, zones in enumerate(self._zones):
            kinds = zones.types[zones.index(s)]
            inner, outer = _GROUND_INNER[kinds][:, None], _GROUND_OUTER[kinds][:, None]
            table[:, side, 4:] = np.where(_BAND_LOWER[None, :] < _GROUND_EDGE[kinds][:, None], inner, outer)
            stripes = table[:, side, _N_BANDS - 1]
            table[:, side, _N_BANDS - 1] = np.where(stripes == _MAT["field_a"], _MAT["field_b"], stripes)
        if len(self._bridge_a):
            j = np.searchsorted(self._bridge_a, s, side="right") - 1
            on_bridge = (j >= 0) & (s < self._bridge_b[np.maximum(j, 0)])
            table[on_bridge, :, 2] = _MAT["steel"]
            table[on_bridge, :, 3:] = _MAT["water"]
        material = np.take(table.ravel() * _LEVELS, view.ground_band_index)
        fine = _texture(self._grain_flat, (s * 3.0)[:, None], view.ground_xi_fine)
        coarse = _texture(self._coarse_flat, (s / 6.0)[:, None], view.ground_xi_coarse)
        level = coarse + (fine * view.grain_amp).astype(np.int32)
        np.add(material, level, out=codes[view.first_ground_row :], casting="unsafe")

    def _draw_rails(self, codes: np.ndarray, view: _View, z_end: float) -> None:
        z0 = view.focal * _CAM_HEIGHT / (view.height - view.horizon) * 0.5
        for x in (-_GAUGE_HALF, _GAUGE_HALF):
            _fill(codes, view, _flat(x - 0.08, x + 0.08, 0.0, z0, z_end), _code("rail_dark", 12))
            _fill(codes, view, _flat(x - 0.035, x + 0.035, 0.16, z0, z_end), _code("rail", 18))

    def _zone_at(self, view: _View, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Zone type, tree height factor and spruce share per column (left columns: left side)."""
        left_zones, right_zones = self._zones
        i_left, i_right = left_zones.index(s), right_zones.index(s)
        left = view.left
        kind = np.where(left, left_zones.types[i_left], right_zones.types[i_right])
        heights = np.where(left, left_zones.heights[i_left], right_zones.heights[i_right])
        spruce = np.where(left, left_zones.spruce[i_left], right_zones.spruce[i_right])
        return kind, heights, spruce

    def _draw_trees(self, codes: np.ndarray, view: _View, p: float, layer: _TreeLayer) -> None:
        """A row of trees: per column the tallest crown covering it (spruce cones, birch domes)."""
        z_all = view.focal * layer.lateral / view.col_dist
        s_all = p + z_all
        kind_all, height_all, spruce_all = self._zone_at(view, s_all)
        occupancy_all = np.asarray(layer.occupancy)[kind_all]
        cols = np.flatnonzero((occupancy_all > 0) & (z_all <= 4000.0))
        if cols.size == 0:
            return
        z, s, occupancy = z_all[cols], s_all[cols], occupancy_all[cols]
        height_scale = height_all[cols] * _ZONE_TREE_SCALE[kind_all[cols]]
        spruce_share = spruce_all[cols]
        side_key = np.where(view.left[cols], 0, 1 << 26)
        position = s / layer.cell
        cell0 = np.floor(position).astype(np.int64)
        # All candidate slots at once: (2 * reach + 1, columns).
        cell = cell0 + np.arange(-layer.reach, layer.reach + 1)[:, None]
        key = cell + side_key
        rand = self._table[:, _slots(key, layer.salt * 104729)]
        spruce = rand[3] < spruce_share
        centre = cell + 0.5 + 0.5 * (rand[1] - 0.5)
        tree_height = (layer.height[0] + (layer.height[1] - layer.height[0]) * rand[2]) * height_scale
        # Crowns are round, not flat: seen obliquely a crown of radius r covers about r*z/X metres
        # of the row; the searched slots bound that width.
        oblique = np.maximum(z / layer.lateral, 1.0) / layer.cell
        radius = np.where(spruce, 0.2, 0.3) * (0.85 + 0.3 * rand[4]) * tree_height
        half_width = np.clip(radius * oblique, 0.3, layer.reach - 0.3)
        rel = (position - centre) / half_width
        d = np.minimum(np.abs(rel), 1.0)
        # Spruce: a cone. Birch: a dome on top of the stand below it.
        shape = np.where(spruce, 1.0 - d, np.where(d < 1.0, 0.5 + 0.5 * np.sqrt(1.0 - d * d), 0.0))
        h = np.where(rand[0] < occupancy, tree_height * shape, 0.0)
        winner = np.argmax(h, axis=0)[None, :]
        best = np.take_along_axis(h, winner, axis=0)[0]
        best_key = np.take_along_axis(key, winner, axis=0)[0]
        best_spruce = np.take_along_axis(spruce, winner, axis=0)[0]
        best_rel = np.take_along_axis(rel, winner, axis=0)[0]
        # Where crowns would be wider than the searched slots, or many trees share a column, draw
        # the stand's average canopy instead of single crowns (a distant tree line).
        typical = 0.25 * (layer.height[0] + layer.height[1]) / 2 * height_scale
        metres_per_column = z * z / (view.focal * layer.lateral)
        crowding = np.maximum(metres_per_column / layer.cell - 0.5, typical * oblique / (layer.reach - 0.3) - 1.0)
        blend = np.clip(crowding, 0.0, 1.0)
        mean_height = 0.7 * (layer.height[0] + layer.height[1]) / 2 * height_scale * occupancy
        best = best + (mean_height - best) * blend
        keep = best > 0.3
        if not keep.any():
            return
        # Columns without a tree get an empty span above the image.
        top = np.where(keep, view.horizon + view.focal * (_CAM_HEIGHT - best) / z, -11.0)
        bottom = np.where(keep, view.horizon + view.focal * _CAM_HEIGHT / z, -10.0)
        r0 = max(int(math.floor(top[keep].min())), 0)
        r1 = min(int(math.ceil(bottom[keep].max())), view.height)
        if r1 <= r0:
            return
        y = view.row_centre[r0:r1, None]
        rel_y = _relative_rows(y, top, bottom)
        inside = (rel_y >= 0.0) & (rel_y < 1.0)
        rand = self._table[5:7, _slots(best_key, layer.salt * 104729)]
        birch = _MAT["birch_a"] + (rand[0] * 3).astype(np.int32)
        dark_code = np.where(best_spruce, _MAT["spruce"], birch) * _LEVELS
        # Light from the left: the left flank of each crown is lighter.
        column_level = np.where(best_rel < 0.0, _MID + 2, _MID - 2).astype(np.int32)
        if layer.detail:
            # Height above ground per pixel, so textures stay fixed to the world.
            row_scale = (z / view.focal).astype(np.float32)
            altitude = (_CAM_HEIGHT + view.horizon * z / view.focal + 4096.0).astype(np.float32) - y * row_scale
            leaves = _texture(self._grain_int_flat, altitude * np.float32(5.0), s * 4.0)
            # Spruce branch whorls whose upper sides catch light and hold snow, broken up by the
            # leaf texture so they read as patches rather than stripes.
            whorl = (altitude * np.float32(256.0 / 1.8) + (rand[1] * 256.0).astype(np.float32)).astype(np.int32) & 255
            lit = whorl + 24 * leaves < 70
            lit_code = np.where(best_spruce, _MAT["spruce_lit"], birch) * _LEVELS
            base = np.where(lit, lit_code, dark_code)
            level = column_level + leaves - (4.0 * rel_y).astype(np.int32)
        else:
            base = dark_code
            level = column_level - (4.0 * rel_y).astype(np.int32)
        if layer.understorey:
            base = np.where(rel_y > 0.85, _MAT["understorey"] * _LEVELS, base)
        block = codes[r0:r1, cols]
        codes[r0:r1, cols] = np.where(inside, base + level, block)

    def _draw_rock(self, codes: np.ndarray, view: _View, p: float, z_max: float) -> None:
        """Rock cuts: jagged grey walls close to the track, up to `z_max` (a tunnel portal)."""
        z = view.focal * _ROCK_LATERAL / view.col_dist
        s = p + z
        kind = self._zone_at(view, s)[0]
        visible = (kind == _ROCKCUT) & (z <= z_max)
        if not visible.any():
            return
        salted = 401 + np.where(view.left, 0, 7000)
        height = 3.0 + 5.0 * _fbm(s / 40.0, salted, self._table[7]) + 1.0 * _fbm(s / 3.0, salted + 17, self._table[7])
        top = view.horizon + view.focal * (_CAM_HEIGHT - height) / z
        bottom = view.horizon + view.focal * _CAM_HEIGHT / z
        r0 = max(int(math.floor(top[visible].min())), 0)
        r1 = min(int(math.ceil(bottom[visible].max())), view.height)
        if r1 <= r0:
            return
        top = np.where(visible, top, -11.0)
        bottom = np.where(visible, bottom, -10.0)
        y = view.row_centre[r0:r1, None]
        rel_y = _relative_rows(y, top, bottom)
        inside = (rel_y >= 0.0) & (rel_y < 1.0)
        # Blasted rock: smooth facets plus fine roughness, fixed to the world.
        row_scale = (z / view.focal).astype(np.float32)
        altitude = (_CAM_HEIGHT + view.horizon * z / view.focal + 4096.0).astype(np.float32) - y * row_scale
        facets = _texture(self._coarse_flat, altitude * np.float32(2.0), s * 0.8)
        grain = _texture(self._grain_int_flat, altitude * np.float32(5.0), s * 4.0)
        base = np.where(rel_y < 0.08, _MAT["rock_top"] * _LEVELS, _MAT["rock"] * _LEVELS)
        sun = np.where(view.left, -2, 2).astype(np.int32)  # the right-hand cut faces the sun
        code = base + 2 * facets - _MID + sun + grain
        np.copyto(codes[r0:r1], code, where=inside, casting="unsafe")

    def _draw_portal(self, codes: np.ndarray, view: _View, z: float, index: int) -> None:
        """The mountain face with a concrete-framed tunnel mouth, seen while approaching."""
        shape = self._tunnel_shape[index]
        left_h, crest, right_h = 14.0 + 10.0 * shape[0], 30.0 + 25.0 * shape[1], 14.0 + 10.0 * shape[2]
        offset = -15.0 + 30.0 * shape[3]
        face = [(-70.0, 0.0, z), (-70.0, left_h, z), (offset, crest, z), (70.0, right_h, z), (70.0, 0.0, z)]
        marker = _code("rock", 0)
        _fill(codes, view, face, marker)
        # Texture the face like the rock cuts: it is a plane, so world coordinates follow from pixels.
        u0, _ = view.project(-70.0, 0.0, z)
        u1, _ = view.project(70.0, 0.0, z)
        _, v0 = view.project(0.0, crest, z)
        r0, r1 = max(int(v0), 0), min(int(math.ceil(view.horizon + view.focal * _CAM_HEIGHT / z)) + 1, view.height)
        c0, c1 = max(int(u0), 0), min(int(math.ceil(u1)) + 1, view.width)
        if r1 > r0 and c1 > c0:
            block = codes[r0:r1, c0:c1]
            x = (view.col_offset[c0:c1] * z / view.focal + 4096.0).astype(np.float32)
            rows = view.row_centre[r0:r1, None]
            altitude = (_CAM_HEIGHT + (view.horizon - rows) * z / view.focal + 4096.0).astype(np.float32)
            facets = _texture(self._coarse_flat, altitude * 0.5, x * 0.5)
            grain = _texture(self._grain_int_flat, altitude * 3.0, x * 3.0)
            textured = _MAT["rock"] * _LEVELS - 3 + 2 * facets - _MID + grain
            np.copyto(block, textured, where=block == marker, casting="unsafe")
        # Vegetation (snow in winter) on the top edge of the face.
        left_top = [(-75.0, left_h - 3, z + 2), (-70.0, left_h, z), (offset, crest, z), (offset, crest + 4, z + 2)]
        right_top = [(offset, crest + 4, z + 2), (offset, crest, z), (70.0, right_h, z), (75.0, right_h - 3, z + 2)]
        _fill(codes, view, left_top, _code("rock_top", 14))
        _fill(codes, view, right_top, _code("rock_top", 12))
        _fill(codes, view, _arch(z, 3.7, 5.0, 7.6), _code("platform", 15))
        _fill(codes, view, _arch(z, 3.0, 4.5, 6.8), _code("tunnel", 1))

    def _tunnel_codes(self, view: _View, z_exit: float, p: float) -> np.ndarray:
        """Inside a tunnel: dark rings lit by the headlights, dim lamps, and the exit when near."""
        codes = np.full((view.height, view.width), _code("tunnel", 0), dtype=np.uint16)
        for z, level in ((1.5, 9), (2.5, 7), (4.0, 5), (7.0, 4), (12.0, 3), (20.0, 2), (35.0, 1), (60.0, 0)):
            if z >= z_exit:
                break
            _fill(codes, view, _arch(z, 3.0, 4.5, 6.8), _code("tunnel", level))
        first = math.ceil((p + 2.0) / 40.0)
        for k in range(first, first + 8):
            z = k * 40.0 - p
            if z >= min(z_exit, 320.0):
                break
            u, v = view.project(2.7 * (1 if k % 2 else -1), 3.4, z)
            radius = max(view.focal * 0.12 / z, 0.6)
            lamp = _code("lamp", max(12 - int(z / 25), 2))
            cv2.circle(codes, (int(u * _SCALE), int(v * _SCALE)), int(radius * _SCALE), lamp, -1, cv2.LINE_8, _SHIFT)
        z_rails = min(z_exit, 80.0)
        for x in (-_GAUGE_HALF, _GAUGE_HALF):
            _fill(codes, view, _flat(x - 0.04, x + 0.04, 0.16, 2.0, z_rails), _code("tunnel", 14))
        if z_exit < 400.0:
            _fill(codes, view, _arch(z_exit, 3.0, 4.5, 6.8), _code("daylight", 16))
        return codes

    # -- discrete objects -------------------------------------------------------------------------

    def _visible_objects(self, codes: np.ndarray, view: _View, p: float,
                         z_max: float) -> list[tuple[float, float, Callable[[], None]]]:
        """Objects ahead as (lateral, distance, draw), sorted far-out first then far-away first."""
        objects: list[tuple[float, float, Callable[[], None]]] = []
        lo, hi = np.searchsorted(self._house_s, [p - 40.0, p + z_max])
        for house in self._houses[lo:hi]:
            objects.append((house[2], house[0] - p, lambda h=house: _draw_house(codes, view, p, *h)))
        lo, hi = np.searchsorted(self._tree_s, [p - 2.0, p + min(z_max, 400.0)])
        for tree in self._trees[lo:hi]:
            # Small trees far away would be a pixel or two: skip them.
            if tree[0] - p < 60.0 * tree[3]:
                objects.append((tree[2], tree[0] - p, lambda tr=tree: _draw_single_tree(codes, view, p, *tr)))
        for at, side in self._stations:
            if at - 200.0 - p < z_max and at + 60.0 - p > -10.0:
                objects.append((1.75, at - p, lambda a=at, sd=side: _draw_platform(codes, view, p, a, sd)))
        if len(self._bridge_a):
            lo, hi = np.searchsorted(self._bridge_b, [p, p + z_max])
            for a, b in zip(self._bridge_a[lo:hi + 1], self._bridge_b[lo:hi + 1]):
                if a - p < z_max and b > p:
                    objects.append((2.6, a - p, lambda a=a, b=b: _draw_truss(codes, view, p, a, b)))
        objects.append((3.6, 0.0, lambda: self._draw_poles(codes, view, p, z_max)))
        objects.sort(key=lambda o: (-o[0], -o[1]))
        return objects

    def _draw_poles(self, codes: np.ndarray, view: _View, p: float, z_max: float) -> None:
        """Telegraph poles beside the track, with their wires."""
        first = math.floor((p - 60.0) / _POLE_SPACING)
        last = math.ceil((p + min(z_max, 400.0)) / _POLE_SPACING)
        keys = np.arange(first, last + 1)
        s = keys * _POLE_SPACING + 6.0 * (self._table[7, _slots(keys, 501)] - 0.5)
        skip = np.zeros(len(keys), dtype=bool)
        for a, b in ((self._bridge_a, self._bridge_b), (self._tunnel_a, self._tunnel_b)):
            if len(a):
                j = np.searchsorted(a, s, side="right") - 1
                skip |= (j >= 0) & (s < b[np.maximum(j, 0)] + 5.0)
        side = np.where(self._table[7, _slots(np.floor(s / 8000.0).astype(np.int64), 503)] < 0.5, -1.0, 1.0)
        runs: list[list[tuple[float, float]]] = [[]]  # (x, z) of pole tops, split where poles are missing
        for k in range(len(keys)):
            if skip[k] or s[k] - p > z_max:
                runs.append([])
                continue
            x, z = 3.6 * side[k], s[k] - p
            runs[-1].append((x, z))
            if z >= _Z_NEAR:
                _segment(codes, view, (x, 0.0, z), (x, 8.0, z), _code("pole", 13), 0.25)
                _segment(codes, view, (x - 0.8, 7.5, z), (x + 0.8, 7.5, z), _code("pole", 11), 0.12)
        for run in runs:
            for dx in (-0.6, 0.6):
                # Each span sags: pole top, lower middle, next pole top.
                points = []
                for (xa, za), (xb, zb) in zip(run[:-1], run[1:]):
                    points += [(xa + dx, 7.45, za), ((xa + xb) / 2 + dx, 7.05, (za + zb) / 2)]
                if run:
                    points.append((run[-1][0] + dx, 7.45, run[-1][1]))
                _polyline(codes, view, points, _code("wire", 10))


def _texture(table: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Look up a flattened 256 x 256 texture table at (row, col) coordinates, wrapping around."""
    return np.take(table, ((rows.astype(np.int32) & 255) << 8) + (cols.astype(np.int32) & 255))


def _flat(x0: float, x1: float, y: float, z0: float, z1: float) -> list[tuple[float, float, float]]:
    """Horizontal quad along the track at height y (rails, platform tops)."""
    return [(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)]


def _along(x: float, y0: float, y1: float, z0: float, z1: float) -> list[tuple[float, float, float]]:
    """Vertical quad parallel to the track at lateral x (facades, platform edges, chords)."""
    return [(x, y0, z0), (x, y0, z1), (x, y1, z1), (x, y1, z0)]


def _facing(x0: float, x1: float, y0: float, y1: float, z: float) -> list[tuple[float, float, float]]:
    """Vertical quad facing the camera at distance z (signs, beams, gable windows)."""
    return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]


def _relative_rows(y: np.ndarray, top: np.ndarray, bottom: np.ndarray) -> np.ndarray:
    """(y - top) / (bottom - top) per pixel as float32: in [0, 1) inside a column's span."""
    scale = 1.0 / np.maximum(bottom - top, 0.05)
    return y * scale.astype(np.float32) - (top * scale).astype(np.float32)


def _arch(z: float, half_width: float, wall: float, crown: float) -> list[tuple[float, float, float]]:
    """Tunnel cross-section (vertical walls, rounded roof) at distance z."""
    points = [(-half_width, 0.0, z)]
    for angle in np.linspace(np.pi, 0.0, 9):
        points.append((half_width * math.cos(angle), wall + (crown - wall) * math.sin(angle), z))
    points.append((half_width, 0.0, z))
    return points


def _draw_house(codes: np.ndarray, view: _View, p: float, s: float, side: int, lateral: float, length: float,
                depth: float, wall: float, roof: float, wall_mat: str, roof_mat: str) -> None:
    """Gabled house with its long side facing the track: facade, near roof slope, front gable."""
    z1, z2 = s - p, s + length - p
    if z2 < _Z_NEAR:
        return
    x_in, x_out, x_ridge = side * lateral, side * (lateral + depth), side * (lateral + depth / 2)
    lit = 18 if side > 0 else 12  # facades facing left catch the sun
    _fill(codes, view, _along(x_in, 0.0, wall, z1, z2), _code(wall_mat, lit))
    if z1 < 150.0:
        for frac in (0.25, 0.6):
            za, zb = z1 + frac * length, z1 + frac * length + 1.2
            _fill(codes, view, _along(x_in, 1.1, 2.3, za, zb), _code("window", 14))
    roof_slope = [(x_in, wall, z1), (x_in, wall, z2), (x_ridge, wall + roof, z2), (x_ridge, wall + roof, z1)]
    _fill(codes, view, roof_slope, _code(roof_mat, 15))
    if z1 >= _Z_NEAR:
        gable = [(x_in, 0.0, z1), (x_out, 0.0, z1), (x_out, wall, z1), (x_ridge, wall + roof, z1), (x_in, wall, z1)]
        _fill(codes, view, gable, _code(wall_mat, 15))
        xw = side * (lateral + depth / 2 - 0.6)
        _fill(codes, view, _facing(xw, xw + side * 1.2, 1.2, 2.3, z1), _code("window", 12))


def _draw_single_tree(codes: np.ndarray, view: _View, p: float, s: float, side: int, lateral: float, height: float,
                      spruce: bool) -> None:
    z = s - p
    if z < 2.0:
        return
    x = side * lateral
    if spruce:
        _segment(codes, view, (x, 0.0, z), (x, 0.2 * height, z), _code("understorey", 14), 0.3)
        for tier in range(3):
            base = (0.12 + 0.25 * tier) * height
            top = min(base + 0.5 * height, height)
            half = 0.2 * height * (1.0 - 0.28 * tier)
            _fill(codes, view, [(x - half, base, z), (x + half, base, z), (x, top, z)], _code("spruce_lit", 15))
            drop = 0.06 * height
            shadow = [(x - 0.92 * half, base - drop / 2, z), (x + 0.92 * half, base - drop / 2, z), (x, top - drop, z)]
            _fill(codes, view, shadow, _code("spruce", 14))
    else:
        _segment(codes, view, (x, 0.0, z), (x, 0.55 * height, z), _code("trunk", 16), 0.25)
        u, v = view.project(x, 0.62 * height, z)
        axes = (view.focal * 0.24 * height / z, view.focal * 0.36 * height / z)
        variant = ("birch_a", "birch_b", "birch_c")[int(s * 7.0) % 3]
        centre, size = (int(u * _SCALE), int(v * _SCALE)), (int(axes[0] * _SCALE) + 1, int(axes[1] * _SCALE) + 1)
        cv2.ellipse(codes, centre, size, 0, 0, 360, _code(variant, 15), -1, cv2.LINE_8, _SHIFT)


def _draw_platform(codes: np.ndarray, view: _View, p: float, at: float, side: int) -> None:
    """Platform along the track, with lamp posts and a station sign facing the train."""
    z1, z2 = max(at - 170.0 - p, _Z_NEAR), at + 30.0 - p
    if z2 < _Z_NEAR:
        return
    xi, xo, top = side * 1.75, side * 5.5, 0.75
    _fill(codes, view, _facing(xi, xo, 0.0, top, z2), _code("platform", 12))
    _fill(codes, view, _along(xi, 0.0, top, z1, z2), _code("platform", 9))
    _fill(codes, view, _flat(xi, xo, top, z1, z2), _code("platform", 17))
    _fill(codes, view, _flat(xi, xi + side * 0.3, top, z1, z2), _code("platform_edge", 16))
    for k in range(int(math.ceil((at - 170.0) / 25.0)), int((at + 30.0) // 25.0) + 1):
        z = k * 25.0 - p
        if _Z_NEAR < z < 300.0:
            _segment(codes, view, (side * 5.0, top, z), (side * 5.0, 4.5, z), _code("steel", 12), 0.12)
            _segment(codes, view, (side * 5.0, 4.5, z), (side * 4.4, 4.5, z), _code("lamp", 18), 0.2)
    z = at + 20.0 - p
    if z > _Z_NEAR:
        for x in (side * 3.3, side * 4.9):
            _segment(codes, view, (x, top, z), (x, 2.4, z), _code("steel", 10), 0.08)
        _fill(codes, view, _facing(side * 3.0, side * 5.2, 2.2, 3.0, z), _code("window", 10))
        _fill(codes, view, _facing(side * 3.1, side * 5.1, 2.3, 2.9, z), _code("sign", 17))


def _draw_truss(codes: np.ndarray, view: _View, p: float, a: float, b: float) -> None:
    """Steel truss bridge over a river: chords, verticals, diagonals and top bracing.

    Members are quads with a world width, so they thin out with distance like real beams."""
    steel, shade = _code("steel", 14), _code("steel", 10)
    za, zb = a - p, b - p
    for x in (-2.6, 2.6):
        for y in (0.6, 6.0):
            _fill(codes, view, _along(x, y - 0.18, y + 0.18, za, zb), steel)
    panel = 8.0
    for k in range(int((b - a) // panel) + 1):
        z = za + k * panel
        if z > 150.0:
            break
        if z + panel < _Z_NEAR:
            continue
        for x in (-2.6, 2.6):
            _fill(codes, view, _facing(x - 0.12, x + 0.12, 0.6, 6.0, z), steel)
            if z + panel <= zb:
                diagonal = [(x - 0.1, 0.6, z), (x + 0.1, 0.6, z), (x + 0.1, 6.0, z + panel), (x - 0.1, 6.0, z + panel)]
                _fill(codes, view, diagonal, shade)
        _fill(codes, view, _facing(-2.6, 2.6, 5.85, 6.15, z), shade)


class _SeasonLook:
    """One season's appearance at one image size: palette, clouds, camera, light drift, noise."""

    _NOISE_FRAMES = 8
    _NOISE_PAD = 8

    def __init__(self, seed: int, season: str, view: _View):
        s_index = SEASONS.index(season)
        self.view = view
        self.s_index, self.seed = s_index, seed
        self.palette = _palette(season)
        width, height = view.width, view.height
        scale = width / 256.0
        rng = np.random.default_rng([seed, s_index, 1])
        # A fixed camera offset per season (the cameras were re-mounted) plus smooth shake.
        self.offset = (rng.uniform(-3.0, 3.0) * scale, rng.uniform(-2.0, 2.0) * scale, rng.uniform(-0.4, 0.4))
        self.jitter_freq = rng.uniform(0.15, 1.2, (2, 3))
        self.jitter_phase = rng.uniform(0.0, 2 * np.pi, (2, 3))
        self.jitter_amp = 0.3 * scale
        self.light_period = rng.uniform(60.0, 300.0, 2)
        self.light_phase = rng.uniform(0.0, 2 * np.pi, 2)
        # Clouds: a wide panorama of soft noise, seamless across its ends, that drifts slowly.
        coverage, colour, opacity = _CLOUDS[season]
        rng = np.random.default_rng([seed, s_index, 2])
        rows, pano = view.first_ground_row, 4 * width
        noise = np.zeros((rows, pano), dtype=np.float32)
        for octave, weight in ((6, 1.0), (14, 0.5), (30, 0.25)):
            grid = np.tile(rng.normal(0.0, 1.0, (max(2, octave // 3), octave)).astype(np.float32), (1, 3))
            noise += weight * cv2.resize(grid, (3 * pano, rows), interpolation=cv2.INTER_CUBIC)[:, pano : 2 * pano]
        threshold = np.quantile(noise, 1.0 - coverage)
        alpha = np.clip((noise - threshold) / (noise.std() * 0.6), 0.0, 1.0) * opacity
        fade = np.clip((view.horizon - view.row_centre[:rows]) / (0.35 * view.horizon), 0.3, 1.0)[:, None]
        self.clouds = np.concatenate([alpha * fade, (alpha * fade)[:, :width]], axis=1).astype(np.float32)
        self.cloud_image = np.empty((rows, width, 3), dtype=np.uint8)
        self.cloud_image[:] = colour[::-1]
        self.cloud_drift = rng.uniform(0.2, 0.6) * scale  # px/s
        rng = np.random.default_rng([seed, s_index, 3, width, height])
        pad = self._NOISE_PAD
        noise = rng.normal(0.0, 2.0, (self._NOISE_FRAMES, height + pad, width + pad, 3))
        self.noise = np.clip(np.rint(noise), -8, 8).astype(np.int16)

    def colourise(self, codes: np.ndarray, t: float, shake: float) -> np.ndarray:
        """Season colours, clouds, camera offset and shake (scaled by `shake`), light drift, noise."""
        view = self.view
        image = np.take(self.palette, codes, axis=0)
        rows = view.first_ground_row
        shift = int(t * self.cloud_drift) % (self.clouds.shape[1] - view.width)
        alpha = self.clouds[:, shift : shift + view.width] * (codes[:rows] < 2 * _LEVELS)  # sky pixels only
        image[:rows] = cv2.blendLinear(image[:rows], self.cloud_image, 1.0 - alpha, alpha)
        dx, dy, angle = self.offset
        jitter = shake * self.jitter_amp * np.sin(2 * np.pi * self.jitter_freq * t + self.jitter_phase).sum(axis=1)
        matrix = cv2.getRotationMatrix2D((view.cx, view.horizon), angle, 1.0)
        matrix[0, 2] += dx + jitter[0]
        matrix[1, 2] += dy + jitter[1]
        image = cv2.warpAffine(image, matrix, (view.width, view.height), flags=cv2.INTER_LINEAR,
                               borderMode=cv2.BORDER_REFLECT_101)
        gain = 1.0 + 0.04 * float(np.sin(2 * np.pi * t / self.light_period + self.light_phase).sum())
        image = cv2.convertScaleAbs(image, alpha=gain)
        key = _mix(self.seed, self.s_index, int(round(t * 1e6)))
        k, oy, ox = key % self._NOISE_FRAMES, (key >> 8) % self._NOISE_PAD, (key >> 16) % self._NOISE_PAD
        noise = self.noise[k, oy : oy + view.height, ox : ox + view.width]
        return cv2.add(image, noise, dtype=cv2.CV_8U)


def render_frame(world: SyntheticRoute, season: str, t: float, width: int, height: int) -> np.ndarray:
    """Cab view of `world` in `season` at video time t: (height, width, 3) uint8 BGR."""
    if not isinstance(world, SyntheticRoute):
        raise ValueError(f"world must be a SyntheticRoute, got {type(world).__name__}")
    return world.frame(season, t, width, height)


def _check_seasons(seasons: Sequence[str]) -> list[str]:
    seasons = list(seasons)
    if not seasons:
        raise ValueError("seasons is empty")
    for season in seasons:
        if season not in SEASONS:
            raise ValueError(f"unknown season {season!r}; expected some of {SEASONS}")
    if len(set(seasons)) != len(seasons):
        raise ValueError(f"seasons contains duplicates: {seasons}")
    return seasons


def render_route(out_dir: Path, seasons: Sequence[str], seconds: int, fps: int, width: int, height: int, seed: int,
                 progress: bool = True) -> RouteLayout:
    """Write out_dir/<season>.mp4 (seconds*fps frames, frame k at time k/fps) and out_dir/layout.json.

    All seasons are rendered side by side so each place's geometry is drawn once. On any error the
    files this call was writing are removed.
    """
    seasons = _check_seasons(seasons)
    if int(fps) != fps or fps < 1:
        raise ValueError(f"fps must be a positive integer, got {fps!r}")
    route = SyntheticRoute(seconds, seed)
    route.frame(seasons[0], 0.0, width, height)  # validates the size before any file is created
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    video_paths = [out_dir / f"{season}.mp4" for season in seasons]
    layout_path = out_dir / "layout.json"
    writers: list[cv2.VideoWriter] = []
    try:
        for path in video_paths:
            writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), float(fps), (int(width), int(height)))
            if not writer.isOpened():
                raise OSError(f"cannot open video writer for {path}")
            writers.append(writer)
        n_frames = route.seconds * int(fps)
        for k in tqdm(range(n_frames), desc="render route", unit="frame", disable=not progress):
            t = k / fps
            for season, writer in zip(seasons, writers):
                writer.write(route.frame(season, t, width, height))
        for writer in writers:
            writer.release()
        writers.clear()
        # OpenCV's writer does not raise when the disk fills: check what it left
        for path in video_paths:
            if not path.is_file() or path.stat().st_size == 0:
                raise OSError(f"{path}: the video was not written (is the disk full?)")
        layout_path.write_text(json.dumps(route.layout.to_json(), indent=1))
    except BaseException:
        for writer in writers:
            writer.release()
        for path in [*video_paths, layout_path]:
            path.unlink(missing_ok=True)
        raise
    return route.layout


def render_preview(path: Path, seconds: int, seed: int, times: Sequence[float], width: int = 256,
                   height: int = 144) -> None:
    """PNG grid: one row per place (video time), one labelled column per season."""
    times = list(times)
    if not times:
        raise ValueError("times is empty")
    route = SyntheticRoute(seconds, seed)
    label_w, header_h, gap = 70, 22, 2
    grid = np.full((header_h + len(times) * (height + gap), label_w + len(SEASONS) * (width + gap), 3), 255, np.uint8)
    font = cv2.FONT_HERSHEY_SIMPLEX
    for col, season in enumerate(SEASONS):
        cv2.putText(grid, season, (label_w + col * (width + gap) + 4, 16), font, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    for row, t in enumerate(times):
        y = header_h + row * (height + gap)
        cv2.putText(grid, f"t={t:g}s", (4, y + height // 2), font, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
        for col, season in enumerate(SEASONS):
            x = label_w + col * (width + gap)
            grid[y : y + height, x : x + width] = route.frame(season, float(t), width, height)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if not cv2.imwrite(str(path), grid):
        raise OSError(f"cannot write preview PNG {path}")
