"""Tunnels: the mountain face and portal seen while approaching, and the view inside."""

from __future__ import annotations

import math

import cv2
import numpy as np

from ..camera import CAM_HEIGHT, SCALE, SHIFT, View, fill, flat
from ..palette import LEVELS, MAT, MID, shade_code
from ..textures import Textures, texture
from .ground import GAUGE_HALF


def arch(z: float, half_width: float, wall: float, crown: float) -> list[tuple[float, float, float]]:
    """Tunnel cross-section (vertical walls, rounded roof) at distance z."""
    points = [(-half_width, 0.0, z)]
    for angle in np.linspace(np.pi, 0.0, 9):
        points.append((half_width * math.cos(angle), wall + (crown - wall) * math.sin(angle), z))
    points.append((half_width, 0.0, z))
    return points


def draw_portal(codes: np.ndarray, view: View, z: float, shape: np.ndarray, textures: Textures) -> None:
    """The mountain face with a concrete-framed tunnel mouth, seen while approaching.

    `shape`: the tunnel's four numbers in [0, 1) for the face's outline (`Landscape.tunnel_shape`)."""
    left_h, crest, right_h = 14.0 + 10.0 * shape[0], 30.0 + 25.0 * shape[1], 14.0 + 10.0 * shape[2]
    offset = -15.0 + 30.0 * shape[3]
    face = [(-70.0, 0.0, z), (-70.0, left_h, z), (offset, crest, z), (70.0, right_h, z), (70.0, 0.0, z)]
    marker = shade_code("rock", 0)
    fill(codes, view, face, marker)
    # Texture the face like the rock cuts: it is a plane, so world coordinates follow from pixels.
    u0, _ = view.project(-70.0, 0.0, z)
    u1, _ = view.project(70.0, 0.0, z)
    _, v0 = view.project(0.0, crest, z)
    r0, r1 = max(int(v0), 0), min(int(math.ceil(view.horizon + view.focal * CAM_HEIGHT / z)) + 1, view.height)
    c0, c1 = max(int(u0), 0), min(int(math.ceil(u1)) + 1, view.width)
    if r1 > r0 and c1 > c0:
        block = codes[r0:r1, c0:c1]
        x = (view.col_offset[c0:c1] * z / view.focal + 4096.0).astype(np.float32)
        rows = view.row_centre[r0:r1, None]
        altitude = (CAM_HEIGHT + (view.horizon - rows) * z / view.focal + 4096.0).astype(np.float32)
        facets = texture(textures.coarse_flat, altitude * 0.5, x * 0.5)
        grain = texture(textures.grain_int_flat, altitude * 3.0, x * 3.0)
        textured = MAT["rock"] * LEVELS - 3 + 2 * facets - MID + grain
        np.copyto(block, textured, where=block == marker, casting="unsafe")
    # Vegetation (snow in winter) on the top edge of the face.
    left_top = [(-75.0, left_h - 3, z + 2), (-70.0, left_h, z), (offset, crest, z), (offset, crest + 4, z + 2)]
    right_top = [(offset, crest + 4, z + 2), (offset, crest, z), (70.0, right_h, z), (75.0, right_h - 3, z + 2)]
    fill(codes, view, left_top, shade_code("rock_top", 14))
    fill(codes, view, right_top, shade_code("rock_top", 12))
    fill(codes, view, arch(z, 3.7, 5.0, 7.6), shade_code("platform", 15))
    fill(codes, view, arch(z, 3.0, 4.5, 6.8), shade_code("tunnel", 1))


def tunnel_codes(view: View, z_exit: float, p: float) -> np.ndarray:
    """Inside a tunnel: dark rings lit by the headlights, dim lamps, and the exit when near."""
    codes = np.full((view.height, view.width), shade_code("tunnel", 0), dtype=np.uint16)
    for z, level in ((1.5, 9), (2.5, 7), (4.0, 5), (7.0, 4), (12.0, 3), (20.0, 2), (35.0, 1), (60.0, 0)):
        if z >= z_exit:
            break
        fill(codes, view, arch(z, 3.0, 4.5, 6.8), shade_code("tunnel", level))
    first = math.ceil((p + 2.0) / 40.0)
    for k in range(first, first + 8):
        z = k * 40.0 - p
        if z >= min(z_exit, 320.0):
            break
        u, v = view.project(2.7 * (1 if k % 2 else -1), 3.4, z)
        radius = max(view.focal * 0.12 / z, 0.6)
        lamp = shade_code("lamp", max(12 - int(z / 25), 2))
        cv2.circle(codes, (int(u * SCALE), int(v * SCALE)), int(radius * SCALE), lamp, -1, cv2.LINE_8, SHIFT)
    z_rails = min(z_exit, 80.0)
    for x in (-GAUGE_HALF, GAUGE_HALF):
        fill(codes, view, flat(x - 0.04, x + 0.04, 0.16, 2.0, z_rails), shade_code("tunnel", 14))
    if z_exit < 400.0:
        fill(codes, view, arch(z_exit, 3.0, 4.5, 6.8), shade_code("daylight", 16))
    return codes
