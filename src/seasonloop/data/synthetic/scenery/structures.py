"""Man-made things beside the track: houses, station platforms, truss bridges, telegraph poles."""

from __future__ import annotations

import math

import numpy as np

from ..camera import Z_NEAR, View, along, facing, fill, flat, polyline, segment
from ..noise import slots
from ..palette import shade_code
from ..textures import Textures
from ..zones import Landscape

POLE_SPACING = 50.0  # m between telegraph poles


def draw_house(
    codes: np.ndarray,
    view: View,
    p: float,
    s: float,
    side: int,
    lateral: float,
    length: float,
    depth: float,
    wall: float,
    roof: float,
    wall_mat: str,
    roof_mat: str,
) -> None:
    """Gabled house with its long side facing the track: facade, near roof slope, front gable."""
    z1, z2 = s - p, s + length - p
    if z2 < Z_NEAR:
        return
    x_in, x_out, x_ridge = side * lateral, side * (lateral + depth), side * (lateral + depth / 2)
    lit = 18 if side > 0 else 12  # facades facing left catch the sun
    fill(codes, view, along(x_in, 0.0, wall, z1, z2), shade_code(wall_mat, lit))
    if z1 < 150.0:
        for frac in (0.25, 0.6):
            za, zb = z1 + frac * length, z1 + frac * length + 1.2
            fill(codes, view, along(x_in, 1.1, 2.3, za, zb), shade_code("window", 14))
    roof_slope = [(x_in, wall, z1), (x_in, wall, z2), (x_ridge, wall + roof, z2), (x_ridge, wall + roof, z1)]
    fill(codes, view, roof_slope, shade_code(roof_mat, 15))
    if z1 >= Z_NEAR:
        gable = [(x_in, 0.0, z1), (x_out, 0.0, z1), (x_out, wall, z1), (x_ridge, wall + roof, z1), (x_in, wall, z1)]
        fill(codes, view, gable, shade_code(wall_mat, 15))
        xw = side * (lateral + depth / 2 - 0.6)
        fill(codes, view, facing(xw, xw + side * 1.2, 1.2, 2.3, z1), shade_code("window", 12))


def draw_platform(codes: np.ndarray, view: View, p: float, at: float, side: int) -> None:
    """Platform along the track, with lamp posts and a station sign facing the train."""
    z1, z2 = max(at - 170.0 - p, Z_NEAR), at + 30.0 - p
    if z2 < Z_NEAR:
        return
    xi, xo, top = side * 1.75, side * 5.5, 0.75
    fill(codes, view, facing(xi, xo, 0.0, top, z2), shade_code("platform", 12))
    fill(codes, view, along(xi, 0.0, top, z1, z2), shade_code("platform", 9))
    fill(codes, view, flat(xi, xo, top, z1, z2), shade_code("platform", 17))
    fill(codes, view, flat(xi, xi + side * 0.3, top, z1, z2), shade_code("platform_edge", 16))
    for k in range(int(math.ceil((at - 170.0) / 25.0)), int((at + 30.0) // 25.0) + 1):
        z = k * 25.0 - p
        if Z_NEAR < z < 300.0:
            segment(codes, view, (side * 5.0, top, z), (side * 5.0, 4.5, z), shade_code("steel", 12), 0.12)
            segment(codes, view, (side * 5.0, 4.5, z), (side * 4.4, 4.5, z), shade_code("lamp", 18), 0.2)
    z = at + 20.0 - p
    if z > Z_NEAR:
        for x in (side * 3.3, side * 4.9):
            segment(codes, view, (x, top, z), (x, 2.4, z), shade_code("steel", 10), 0.08)
        fill(codes, view, facing(side * 3.0, side * 5.2, 2.2, 3.0, z), shade_code("window", 10))
        fill(codes, view, facing(side * 3.1, side * 5.1, 2.3, 2.9, z), shade_code("sign", 17))


def draw_truss(codes: np.ndarray, view: View, p: float, a: float, b: float) -> None:
    """Steel truss bridge over a river: chords, verticals, diagonals and top bracing.

    Members are quads with a world width, so they thin out with distance like real beams."""
    steel, shade = shade_code("steel", 14), shade_code("steel", 10)
    za, zb = a - p, b - p
    for x in (-2.6, 2.6):
        for y in (0.6, 6.0):
            fill(codes, view, along(x, y - 0.18, y + 0.18, za, zb), steel)
    panel = 8.0
    for k in range(int((b - a) // panel) + 1):
        z = za + k * panel
        if z > 150.0:
            break
        if z + panel < Z_NEAR:
            continue
        for x in (-2.6, 2.6):
            fill(codes, view, facing(x - 0.12, x + 0.12, 0.6, 6.0, z), steel)
            if z + panel <= zb:
                diagonal = [(x - 0.1, 0.6, z), (x + 0.1, 0.6, z), (x + 0.1, 6.0, z + panel), (x - 0.1, 6.0, z + panel)]
                fill(codes, view, diagonal, shade)
        fill(codes, view, facing(-2.6, 2.6, 5.85, 6.15, z), shade)


def draw_poles(codes: np.ndarray, view: View, p: float, z_max: float, land: Landscape, textures: Textures) -> None:
    """Telegraph poles beside the track, with their wires."""
    first = math.floor((p - 60.0) / POLE_SPACING)
    last = math.ceil((p + min(z_max, 400.0)) / POLE_SPACING)
    keys = np.arange(first, last + 1)
    s = keys * POLE_SPACING + 6.0 * (textures.table[7, slots(keys, 501)] - 0.5)
    skip = np.zeros(len(keys), dtype=bool)
    for a, b in ((land.bridge_a, land.bridge_b), (land.tunnel_a, land.tunnel_b)):
        if len(a):
            j = np.searchsorted(a, s, side="right") - 1
            skip |= (j >= 0) & (s < b[np.maximum(j, 0)] + 5.0)
    side = np.where(textures.table[7, slots(np.floor(s / 8000.0).astype(np.int64), 503)] < 0.5, -1.0, 1.0)
    runs: list[list[tuple[float, float]]] = [[]]  # (x, z) of pole tops, split where poles are missing
    for k in range(len(keys)):
        if skip[k] or s[k] - p > z_max:
            runs.append([])
            continue
        x, z = 3.6 * side[k], s[k] - p
        runs[-1].append((x, z))
        if z >= Z_NEAR:
            segment(codes, view, (x, 0.0, z), (x, 8.0, z), shade_code("pole", 13), 0.25)
            segment(codes, view, (x - 0.8, 7.5, z), (x + 0.8, 7.5, z), shade_code("pole", 11), 0.12)
    for run in runs:
        for dx in (-0.6, 0.6):
            # Each span sags: pole top, lower middle, next pole top.
            points = []
            for (xa, za), (xb, zb) in zip(run[:-1], run[1:]):
                points += [(xa + dx, 7.45, za), ((xa + xb) / 2 + dx, 7.05, (za + zb) / 2)]
            if run:
                points.append((run[-1][0] + dx, 7.45, run[-1][1]))
            polyline(codes, view, points, shade_code("wire", 10))
