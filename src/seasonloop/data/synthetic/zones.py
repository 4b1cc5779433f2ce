"""Scenery zones along the route and what overrides them: stations, tunnels (rock cuts) and bridges.

`Landscape` holds, per side of the track, which zone (forest, meadow, field, water, village, rock
cut, moor) covers each stretch of route, and where the stations, tunnels and bridges are (metres).
The ground each zone shows beside the track is defined here too (`GROUND`, `GROUND_BANDS`).
"""

from __future__ import annotations

import numpy as np

from ..layout import RouteLayout
from .motion import Motion
from .palette import MAT

PORTAL_APPROACH = 450.0  # m of rock cut in front of a tunnel portal
PORTAL_EXIT = 120.0  # m of rock cut behind a tunnel exit
STATION_BEFORE, STATION_AFTER = 350.0, 250.0  # m of station surroundings around a stop

FOREST, MEADOW, FIELD, WATER, VILLAGE, ROCKCUT, MOOR = range(7)
N_ZONES = 7
# Ground per zone: material near the track (3.2 m to the edge), edge distance, material beyond.
GROUND = {
    FOREST: ("verge", 5.0, "forest_floor"),
    MEADOW: ("grass", 5.0, "grass"),
    FIELD: ("grass", 6.0, "field_a"),
    WATER: ("rock", 5.0, "water"),
    VILLAGE: ("grass", 5.0, "grass"),
    ROCKCUT: ("ballast", 4.4, "rock"),
    MOOR: ("moor", 4.5, "moor"),
}
# Lateral bands of the ground (m from the track centre): ballast with sleepers, ballast, shoulder
# (bridge deck edge), shoulder, then bands whose lower bounds are `BAND_LOWER`; the last two
# bands are alternate stripes of a ploughed field.
GROUND_BANDS = np.array([1.25, 1.6, 1.9, 3.2, 4.4, 4.5, 5.0, 6.0])
BAND_LOWER = np.array([3.2, 4.4, 4.5, 5.0, 6.0, 6.0])
N_BANDS = len(GROUND_BANDS) + 2
GROUND_INNER = np.array([MAT[GROUND[k][0]] for k in range(N_ZONES)])
GROUND_EDGE = np.array([GROUND[k][1] for k in range(N_ZONES)])
GROUND_OUTER = np.array([MAT[GROUND[k][2]] for k in range(N_ZONES)])
# Regions give long stretches their character: zone weights and the share of spruce vs birch.
REGIONS = (
    # coast
    ({WATER: 0.32, FIELD: 0.2, MEADOW: 0.16, FOREST: 0.14, VILLAGE: 0.12, ROCKCUT: 0.06}, 0.4),
    # forested valley
    ({FOREST: 0.48, MEADOW: 0.2, FIELD: 0.1, WATER: 0.1, ROCKCUT: 0.07, VILLAGE: 0.05}, 0.75),
    # farmland
    ({FIELD: 0.42, MEADOW: 0.2, VILLAGE: 0.16, FOREST: 0.16, WATER: 0.06}, 0.5),
    # mountain plateau (Saltfjellet-like): moor, birch scrub, lakes
    ({MOOR: 0.45, ROCKCUT: 0.12, FOREST: 0.15, WATER: 0.18, MEADOW: 0.1}, 0.1),
)


class Zones:
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


def _zone_segments(rng: np.random.Generator, end: float) -> tuple[list, ...]:
    """Random zone segments up to `end` (m) within regions; rivers with a bridge now and then.

    Returns (starts, left kinds, right kinds, left heights, right heights, spruce shares, bridges).
    """
    starts, left, right, heights_l, heights_r, spruce = [], [], [], [], [], []
    bridges = []
    s = -1000.0
    region_end = -np.inf
    while s < end:
        if s >= region_end:
            region_types, spruce_share = REGIONS[int(rng.integers(len(REGIONS)))]
            kinds = np.array(list(region_types))
            weights = np.array([region_types[k] for k in kinds])
            weights = weights / weights.sum()
            region_end = s + rng.uniform(3000.0, 12000.0)
        length = rng.uniform(120.0, 600.0)
        if rng.random() < 0.06:  # a river with a bridge
            span = rng.uniform(40.0, 160.0)
            bridges.append((s + 30.0, s + 30.0 + span))
            length = span + 60.0
            kind_l = kind_r = WATER
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
    return starts, left, right, heights_l, heights_r, spruce, bridges


class Landscape:
    """Zones per side (`sides`: left, right), stations, tunnels and bridges, all in route metres."""

    def __init__(self, rng: np.random.Generator, layout: RouteLayout, motion: Motion):
        starts, left, right, heights_l, heights_r, spruce, bridges = _zone_segments(rng, motion.length + 4000.0)
        starts_a = np.array(starts)
        self.sides = (
            Zones(starts_a, np.array(left, dtype=np.int64), np.array(heights_l), np.array(spruce)),
            Zones(starts_a.copy(), np.array(right, dtype=np.int64), np.array(heights_r), np.array(spruce)),
        )
        # The overrides draw from `rng` in this order: stations, then the tunnels' shapes.
        blocked = self._place_stations(rng, layout, motion)
        blocked += self._place_tunnels(rng, layout, motion)
        kept = [(a, b) for a, b in bridges if not any(a < y and x < b for x, y in blocked)]
        self.bridge_a = np.array([a for a, _ in kept])
        self.bridge_b = np.array([b for _, b in kept])

    def _place_stations(self, rng: np.random.Generator, layout: RouteLayout, motion: Motion) -> list:
        """A village on one side of each stop, a meadow on the other; returns the stretches used."""
        blocked = []
        self.stations = []
        for start, _ in layout.stops:
            at = float(motion.position(start))
            side = 1 if rng.random() < 0.5 else -1
            a, b = at - STATION_BEFORE, at + STATION_AFTER
            self.sides[0 if side < 0 else 1].paint(a, b, VILLAGE)
            self.sides[1 if side < 0 else 0].paint(a, b, MEADOW)
            blocked.append((a, b))
            self.stations.append((at, side))
        return blocked

    def _place_tunnels(self, rng: np.random.Generator, layout: RouteLayout, motion: Motion) -> list:
        """Rock cuts on both sides around each tunnel; returns the stretches used."""
        blocked = []
        tunnels = []
        for start, stop in layout.tunnels:
            a, b = float(motion.position(start)), float(motion.position(stop))
            for zones in self.sides:
                zones.paint(a - PORTAL_APPROACH, b + PORTAL_EXIT, ROCKCUT)
            blocked.append((a - PORTAL_APPROACH, b + PORTAL_EXIT))
            tunnels.append((a, b))
        self.tunnel_a = np.array([a for a, _ in tunnels])
        self.tunnel_b = np.array([b for _, b in tunnels])
        self.tunnel_shape = rng.uniform(0.0, 1.0, (len(tunnels), 4))  # the portal's mountain face
        return blocked

    def zone_at(self, left: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Zone type, tree height factor and spruce share per column (`left` columns: left side)."""
        left_zones, right_zones = self.sides
        i_left, i_right = left_zones.index(s), right_zones.index(s)
        kind = np.where(left, left_zones.types[i_left], right_zones.types[i_right])
        heights = np.where(left, left_zones.heights[i_left], right_zones.heights[i_right])
        spruce = np.where(left, left_zones.spruce[i_left], right_zones.spruce[i_right])
        return kind, heights, spruce
