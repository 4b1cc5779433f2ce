"""Rock cuts: jagged, textured walls close to the track, where the route is blasted through rock."""

from __future__ import annotations

import math

import numpy as np

from ..camera import CAM_HEIGHT, View, relative_rows
from ..noise import fbm
from ..palette import LEVELS, MAT, MID
from ..textures import Textures, texture
from ..zones import ROCKCUT, Landscape

ROCK_LATERAL = 4.5  # m from the track centre to the rock walls


def draw_rock(codes: np.ndarray, view: View, p: float, z_max: float, land: Landscape, textures: Textures) -> None:
    """Rock cuts: jagged grey walls close to the track, up to `z_max` (a tunnel portal)."""
    z = view.focal * ROCK_LATERAL / view.col_dist
    s = p + z
    kind = land.zone_at(view.left, s)[0]
    visible = (kind == ROCKCUT) & (z <= z_max)
    if not visible.any():
        return
    salted = 401 + np.where(view.left, 0, 7000)
    height = 3.0 + 5.0 * fbm(s / 40.0, salted, textures.table[7]) + 1.0 * fbm(s / 3.0, salted + 17, textures.table[7])
    top = view.horizon + view.focal * (CAM_HEIGHT - height) / z
    bottom = view.horizon + view.focal * CAM_HEIGHT / z
    r0 = max(int(math.floor(top[visible].min())), 0)
    r1 = min(int(math.ceil(bottom[visible].max())), view.height)
    if r1 <= r0:
        return
    top = np.where(visible, top, -11.0)
    bottom = np.where(visible, bottom, -10.0)
    y = view.row_centre[r0:r1, None]
    rel_y = relative_rows(y, top, bottom)
    inside = (rel_y >= 0.0) & (rel_y < 1.0)
    # Blasted rock: smooth facets plus fine roughness, fixed to the world.
    row_scale = (z / view.focal).astype(np.float32)
    altitude = (CAM_HEIGHT + view.horizon * z / view.focal + 4096.0).astype(np.float32) - y * row_scale
    facets = texture(textures.coarse_flat, altitude * np.float32(2.0), s * 0.8)
    grain = texture(textures.grain_int_flat, altitude * np.float32(5.0), s * 4.0)
    base = np.where(rel_y < 0.08, MAT["rock_top"] * LEVELS, MAT["rock"] * LEVELS)
    sun = np.where(view.left, -2, 2).astype(np.int32)  # the right-hand cut faces the sun
    code = base + 2 * facets - MID + sun + grain
    np.copyto(codes[r0:r1], code, where=inside, casting="unsafe")
