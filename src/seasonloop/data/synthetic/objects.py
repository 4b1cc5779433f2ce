"""Discrete objects beside the track: houses and single trees per zone, placed once per route."""

from __future__ import annotations

import numpy as np

from .zones import FIELD, MEADOW, MOOR, VILLAGE, Landscape

_HOUSE_COLOURS = ("house_red", "house_white", "house_yellow")


class RouteObjects:
    """Houses and single trees sorted by route position (`house_s`, `tree_s`) for range lookups.

    Placed after the zone overrides (stations, tunnels), from the world's generator.
    """

    def __init__(self, rng: np.random.Generator, land: Landscape, length: float):
        houses: list[tuple] = []  # s, side, lateral, length, depth, wall, roof, wall mat, roof mat
        trees: list[tuple] = []  # s, side, lateral, height, spruce?
        colours = _HOUSE_COLOURS
        for at, side in land.stations:
            wall = colours[int(rng.integers(3))]
            houses.append((at + 8.0, side, 9.0, 20.0, 9.0, 5.5, 3.0, wall, "roof_dark"))
        for side, zones in zip((-1, 1), land.sides):
            for a, b, kind in zones.segments():
                b = min(b, length + 1000.0)
                if b <= a:
                    continue
                if kind == VILLAGE:
                    _village(rng, houses, trees, land, side, a, b)
                elif kind == FIELD and b - a > 150.0 and rng.random() < 0.6:
                    s = rng.uniform(a, b - 60.0)
                    lateral = rng.uniform(30.0, 90.0)
                    houses.append((s, side, lateral, 12.0, 9.0, 5.0, 3.0, "house_white", "roof_dark"))
                    houses.append((s + 25.0, side, lateral + 5.0, 24.0, 12.0, 6.0, 4.5, "house_red", "roof_dark"))
                if kind in (FIELD, MEADOW, MOOR, VILLAGE):
                    _single_trees(rng, trees, kind, side, a, b)
        houses.sort(key=lambda h: h[0])
        trees.sort(key=lambda tr: tr[0])
        self.houses = houses
        self.house_s = np.array([h[0] for h in houses])
        self.trees = trees
        self.tree_s = np.array([tr[0] for tr in trees])


def _village(
    rng: np.random.Generator, houses: list, trees: list, land: Landscape, side: int, a: float, b: float
) -> None:
    """Houses along [a, b), some with a tree, leaving room for a station building."""
    station_sides = [at for at, station_side in land.stations if station_side == side]
    colours = _HOUSE_COLOURS
    s = a + rng.uniform(0.0, 30.0)
    while s < b - 15.0:
        if any(at - 30.0 < s < at + 40.0 for at in station_sides):
            s += 10.0  # leave room for the station building
            continue
        colour = colours[int(rng.choice(3, p=(0.35, 0.4, 0.25)))]
        roof = "roof_dark" if rng.random() < 0.6 else "roof_red"
        houses.append(
            (
                s,
                side,
                rng.uniform(9.0, 30.0),
                rng.uniform(8.0, 14.0),
                rng.uniform(6.0, 10.0),
                rng.uniform(3.0, 5.5),
                rng.uniform(2.0, 3.5),
                colour,
                roof,
            )
        )
        if rng.random() < 0.5:
            lateral, height = rng.uniform(6.0, 14.0), rng.uniform(6.0, 14.0)
            trees.append((s + rng.uniform(5.0, 20.0), side, lateral, height, rng.random() < 0.4))
        s += rng.uniform(25.0, 60.0)


def _single_trees(rng: np.random.Generator, trees: list, kind: int, side: int, a: float, b: float) -> None:
    """A few free-standing trees in open country (low birch scrub on the moor)."""
    count = int(rng.poisson({FIELD: 2.0, MEADOW: 3.0, MOOR: 8.0, VILLAGE: 2.0}[kind]))
    small = kind == MOOR
    for _ in range(count):
        height = rng.uniform(2.0, 5.0) if small else rng.uniform(7.0, 16.0)
        spruce = (not small) and rng.random() < 0.5
        trees.append((rng.uniform(a, b), side, rng.uniform(6.0, 60.0), height, spruce))
