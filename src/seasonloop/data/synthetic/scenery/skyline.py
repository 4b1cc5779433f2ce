"""The skyline: a mountain range ahead that morphs slowly, and hill ridges beside the track."""

from __future__ import annotations

import math

import numpy as np

from ..camera import CAM_HEIGHT, View
from ..noise import fbm, smoothstep
from ..palette import LEVELS, MAT, MID
from ..textures import Textures, texture
from ..zones import Landscape

HILLS = ((1300.0, 150.0, 650.0, 2500.0, 21), (420.0, 60.0, 260.0, 900.0, 22))  # X, base, relief, scale, salt
MOUNTAIN_DISTANCE = 10000.0  # m, the skyline range straight ahead
# Skyline codes by (layer 0: range ahead, 4: hills) + altitude band (low, bare, snow patch, top).
SKYLINE_CODES = np.array(
    [MAT[name] * LEVELS for name in ("mtn_low", "mtn_rock", "mtn_patch", "mtn_top")]
    + [MAT[name] * LEVELS for name in ("hill_forest", "hill_bare", "hill_patch", "hill_patch")],
    dtype=np.int32,
)


def skyline_layers(
    view: View, p: float, land: Landscape, textures: Textures
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Per column (distance, skyline height above rail, position along the ridge) of the
    mountain range ahead (index 0) and of the far and near hill ridges beside the track (1, 2)."""
    distance = np.full(view.width, MOUNTAIN_DISTANCE)
    # The range ahead morphs slowly as the train advances (every 6 km it has become a new
    # range): the farthest layer changes slowest.
    a = view.col_offset / view.focal * MOUNTAIN_DISTANCE / 1800.0
    morph = p / 6000.0
    m0 = math.floor(morph)
    w = float(smoothstep(np.array(morph - m0)))
    if view.ranges[0] != m0:
        view.ranges = (
            m0,
            fbm(a + 37.0 * m0, 301, textures.table[7], 4),
            fbm(a + 37.0 * (m0 + 1.0), 301, textures.table[7], 4),
        )
    _, h0, h1 = view.ranges
    assert h0 is not None and h1 is not None, "set just above"
    heights = 250.0 + 1150.0 * np.clip((h0 + (h1 - h0) * w) * 1.6 - 0.45, 0.0, 1.0)
    layers = [(distance, heights, a * 1800.0)]
    for lateral, base, relief, scale, salt in HILLS:
        # Ridges parallel to the track: nearer ridges sweep outward faster (parallax).
        z = view.focal * lateral / view.col_dist
        s = p + z
        salted = salt + np.where(view.left, 0, 5000)
        heights = base + relief * np.clip(1.5 * fbm(s / scale, salted, textures.table[7]) - 0.25, 0.0, 1.0)
        if lateral < 1000.0 and len(land.tunnel_a):
            # The mountain a tunnel goes through rises over the nearer ridge.
            j = np.clip(np.searchsorted(land.tunnel_a, s), 0, len(land.tunnel_a) - 1)
            centre = (land.tunnel_a[j] + land.tunnel_b[j]) / 2.0
            half = (land.tunnel_b[j] - land.tunnel_a[j]) / 2.0 + 700.0
            heights = heights + 320.0 * np.cos(np.clip((s - centre) / half, -1.0, 1.0) * np.pi / 2) ** 2
        layers.append((z, heights, s))
    return layers


def draw_skyline(codes: np.ndarray, view: View, p: float, land: Landscape, textures: Textures) -> None:
    """Mountains and hills in one pass over the rows above the horizon: each pixel shows the
    nearest layer covering it, banded by altitude into forest, bare rock, snow patches and
    snow-capped tops. (Below the horizon these layers are farther than the ground there.)"""
    layers = skyline_layers(view, p, land, textures)
    width = view.width
    tops = np.empty((3, width), dtype=np.float32)
    per_column = np.empty((5, 3, width), dtype=np.float32)  # offset, scale, level, texture col, grain col
    for index, (z, heights, along) in enumerate(layers):
        tops[index] = view.horizon + view.focal * (CAM_HEIGHT - heights) / z
        # altitude(y) = offset - y * scale
        per_column[0, index] = view.horizon * z / view.focal
        per_column[1, index] = z / view.focal
        # Slopes facing the sun (left) are lighter; farther layers are hazier.
        haze = (1, 2, 0)[index]
        per_column[2, index] = MID + haze - np.rint(3.0 * np.clip(np.gradient(tops[index]), -1.5, 1.5))
        per_column[3, index] = (along / 90.0).astype(np.int64) & 255
        per_column[4, index] = (along / 12.0).astype(np.int64) & 255
    r0 = max(int(math.floor(tops.min())), 0)
    r1 = view.first_ground_row
    if r1 <= r0:
        return
    y = view.row_centre[r0:r1, None]
    near, far, ahead = y >= tops[2], y >= tops[1], y >= tops[0]
    # Flat index of the covering layer's per-column values.
    flat_index = np.where(near, 2 * width, np.where(far, width, 0)) + view.col_index
    offset, scale, level, tex_col, grain_col = (np.take(values, flat_index) for values in per_column)
    altitude = offset - y * scale
    patch = texture(textures.patches_flat, altitude * np.float32(1.0 / 40.0), tex_col)
    band = np.where(altitude > 330.0 + 70.0 * patch, 1, 0)
    band = np.where((altitude > 560.0) & (patch > 0.0), 2, band)
    band = np.where(altitude > 950.0 + 80.0 * patch, 3, band)
    # Fine grain: stands of forest and scree on the slopes.
    grain = texture(textures.grain_flat, altitude * np.float32(1.0 / 6.0), grain_col)
    hills = flat_index >= width
    code = np.take(SKYLINE_CODES, band + 4 * hills) + (level + patch + grain).astype(np.int32)
    np.copyto(codes[r0:r1], code, where=ahead | far | near, casting="unsafe")
