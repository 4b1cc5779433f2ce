"""The ground plane: ballast and sleepers, shoulders, each side's zone ground, bridges; the rails."""

from __future__ import annotations

import numpy as np

from ..camera import CAM_HEIGHT, View, fill, flat
from ..palette import LEVELS, MAT, shade_code
from ..textures import Textures, texture
from ..zones import BAND_LOWER, GROUND_EDGE, GROUND_INNER, GROUND_OUTER, N_BANDS, Landscape

GAUGE_HALF = 0.7175  # m, half the standard gauge


def draw_ground(codes: np.ndarray, view: View, p: float, land: Landscape, textures: Textures) -> None:
    """Ground plane: ballast and sleepers, shoulder, and each side's zone ground.

    Each pixel belongs to a fixed lateral band (`GROUND_BANDS`); per frame only a small
    (row, side, band) table of materials is built and looked up.
    """
    s = p + view.ground_z
    table = np.empty((len(s), 2, N_BANDS), dtype=np.int32)
    sleeper_rows = (view.ground_z < 12.0) & (np.mod(s, 0.6) < 0.22)
    table[:, :, 0] = np.where(sleeper_rows, MAT["sleeper"], MAT["ballast"])[:, None]
    table[:, :, 1] = MAT["ballast"]
    table[:, :, 2:4] = MAT["verge"]
    for side, zones in enumerate(land.sides):
        kinds = zones.types[zones.index(s)]
        inner, outer = GROUND_INNER[kinds][:, None], GROUND_OUTER[kinds][:, None]
        table[:, side, 4:] = np.where(BAND_LOWER[None, :] < GROUND_EDGE[kinds][:, None], inner, outer)
        stripes = table[:, side, N_BANDS - 1]
        table[:, side, N_BANDS - 1] = np.where(stripes == MAT["field_a"], MAT["field_b"], stripes)
    if len(land.bridge_a):
        j = np.searchsorted(land.bridge_a, s, side="right") - 1
        on_bridge = (j >= 0) & (s < land.bridge_b[np.maximum(j, 0)])
        table[on_bridge, :, 2] = MAT["steel"]
        table[on_bridge, :, 3:] = MAT["water"]
    material = np.take(table.ravel() * LEVELS, view.ground_band_index)
    fine = texture(textures.grain_flat, (s * 3.0)[:, None], view.ground_xi_fine)
    coarse = texture(textures.coarse_flat, (s / 6.0)[:, None], view.ground_xi_coarse)
    level = coarse + (fine * view.grain_amp).astype(np.int32)
    np.add(material, level, out=codes[view.first_ground_row :], casting="unsafe")


def draw_rails(codes: np.ndarray, view: View, z_end: float) -> None:
    """Both rails from the bottom of the image to `z_end` (a tunnel portal or the far distance)."""
    z0 = view.focal * CAM_HEIGHT / (view.height - view.horizon) * 0.5
    for x in (-GAUGE_HALF, GAUGE_HALF):
        fill(codes, view, flat(x - 0.08, x + 0.08, 0.0, z0, z_end), shade_code("rail_dark", 12))
        fill(codes, view, flat(x - 0.035, x + 0.035, 0.16, z0, z_end), shade_code("rail", 18))
